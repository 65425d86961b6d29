//! Layers of one panel: two thin sheets of one material lying flat against each other, each
//! covering most of the other, are one panel (a door's outer skin and its inner liner, a
//! screen's back shell and its bezel, a board and its veneer), so they join. Sheets of two
//! materials stay apart, as every part of the stage is of one material (a laptop's glass screen
//! on its aluminium lid).
//!
//! Why: real meshes build a door or a lid from a stack of sheets, and the views cut them apart
//! where one sheet's edge stands out of the other. Each layer then competes for the panel, and
//! the panel is found only in part (measured on the shared PartNet-Mobility objects,
//! `decompose-bench --partnet`: refrigerator and microwave doors, laptop screens).
//!
//! Only broad sheets are layers: stacked bars may be the links of a linkage that turn about a
//! pin through both (scissors, pliers, the two bars of a walking robot's leg). Covering is
//! judged on the sheets' material, not their outlines: a door closed against a face frame covers
//! the frame's opening, which the frame does not cover back. A sheet held between two others,
//! one on each face, is not joined to them: it may slide or turn in its own plane between them
//! (the two outer ones, stacked across its thickness, still join each other). A stack that would
//! hold nearly the whole object is left apart: the object is then the stack itself (a closed
//! laptop's screen on its base), not a panel of it.

use uniphys_geometry::{DVec3, TriMesh, projection_range};

use crate::candidates::{UnionFind, relabel_by_first_face};
use crate::part_faces::PartFaces;
use crate::sheet_shape::SheetShape;

/// Tuning of [`merge_layers`]. Lengths are shares of the bounds diagonal or of a sheet's length.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerOptions {
    /// A part is a sheet when its thickness is at most this share of its length ...
    /// Default 0.15.
    pub thin_ratio_max: f64,
    /// ... and a broad one when its width is at least this share of its length. Stacked bars
    /// may be the links of a linkage that turn about a pin through both (scissors, pliers, a
    /// walking robot's two leg bars), so only broad sheets are layers. Default 0.25.
    pub broad_ratio_min: f64,
    /// Two sheets lie flat against each other when their normals are this parallel (cosine).
    /// Default 0.95.
    pub parallel_cos_min: f64,
    /// ... with at most this gap between them, a share of the bounds diagonal. Default 0.02.
    pub gap_rel_max: f64,
    /// ... and the two together still a sheet: their joint thickness at most this share of the
    /// longer one's length. Default 0.15.
    pub stack_ratio_max: f64,
    /// Each sheet's material seen across the stack: the other covers at least this share of its
    /// cells, of the larger one's too. Default 0.6.
    pub cover_min: f64,
    /// Parts below this share of the total area are left alone. Default 0.003.
    pub area_fraction_min: f64,
    /// A stack never grows to this share of the total area. Default 0.9.
    pub whole_fraction_max: f64,
    /// Samples per sheet for the covering test. Default 4000.
    pub samples: usize,
    /// Cells along each side of the grid the covering is counted on. Default 24.
    pub grid_cells: usize,
}

impl Default for LayerOptions {
    fn default() -> Self {
        Self {
            thin_ratio_max: 0.15,
            broad_ratio_min: 0.25,
            parallel_cos_min: 0.95,
            gap_rel_max: 0.02,
            stack_ratio_max: 0.15,
            cover_min: 0.6,
            area_fraction_min: 0.003,
            whole_fraction_max: 0.9,
            samples: 4000,
            grid_cells: 24,
        }
    }
}

/// A broad thin part and its shape.
struct Sheet {
    part: usize,
    area_m2: f64,
    shape: SheetShape,
}

impl Sheet {
    /// `None` unless the part is a broad thin sheet.
    fn of(
        mesh: &TriMesh,
        part: usize,
        faces: &[usize],
        area_m2: f64,
        options: &LayerOptions,
    ) -> Option<Self> {
        let corners: Vec<DVec3> = faces.iter().flat_map(|&f| mesh.corners(f)).collect();
        let shape = SheetShape::of(&mesh.submesh(faces), corners, options.samples, part as u64)?;
        shape
            .is_broad_sheet(options.thin_ratio_max, options.broad_ratio_min)
            .then_some(Self {
                part,
                area_m2,
                shape,
            })
    }
}

/// Which face of `sheet` (along its normal: true for the positive one) `other` lies on: at
/// least half of `other`'s thickness beyond that face. `None` for a layer set into the sheet (a
/// panel inset into a door's face).
fn side_of(other: &Sheet, sheet: &Sheet) -> Option<bool> {
    let n = sheet.shape.axes[2];
    let (lo, hi) = projection_range(&sheet.shape.corners, n);
    let (other_lo, other_hi) = projection_range(&other.shape.corners, n);
    let half_m = 0.5 * (other_hi - other_lo);
    if other_hi - other_lo.max(hi) >= half_m {
        Some(true)
    } else if other_hi.min(lo) - other_lo >= half_m {
        Some(false)
    } else {
        None
    }
}

/// How two sheets lie against each other, in the frame of the first.
struct Stack {
    /// Gap between them along the normal, metres (0 when they overlap).
    gap_m: f64,
    /// Their joint thickness along the normal, metres.
    thickness_m: f64,
    /// Share of the larger sheet's covered cells that the other sheet covers too.
    cover: f64,
}

impl Stack {
    fn of(a: &Sheet, b: &Sheet, cells: usize) -> Self {
        let n = a.shape.axes[2];
        let (a_lo, a_hi) = projection_range(&a.shape.corners, n);
        let (b_lo, b_hi) = projection_range(&b.shape.corners, n);
        let gap_m = (b_lo - a_hi).max(a_lo - b_hi).max(0.0);
        let thickness_m = a_hi.max(b_hi) - a_lo.min(b_lo);
        Self {
            gap_m,
            thickness_m,
            cover: covering(a, b, cells),
        }
    }
}

/// Both sheets' samples seen along the first one's normal on one grid over their joint
/// outline: the share of the larger set of covered cells that both cover.
fn covering(a: &Sheet, b: &Sheet, cells: usize) -> f64 {
    let [u, v, _] = a.shape.axes;
    let span = |d: DVec3| {
        let (a_lo, a_hi) = projection_range(&a.shape.corners, d);
        let (b_lo, b_hi) = projection_range(&b.shape.corners, d);
        (a_lo.min(b_lo), a_hi.max(b_hi))
    };
    let ((u_lo, u_hi), (v_lo, v_hi)) = (span(u), span(v));
    let index = |x: f64, lo: f64, hi: f64| {
        (((x - lo) / (hi - lo).max(f64::MIN_POSITIVE) * cells as f64) as usize).min(cells - 1)
    };
    let cell_of = |p: &DVec3| index(p.dot(u), u_lo, u_hi) * cells + index(p.dot(v), v_lo, v_hi);
    let grid = |sheet: &Sheet| {
        let mut covered = vec![false; cells * cells];
        for p in &sheet.shape.samples {
            covered[cell_of(p)] = true;
        }
        covered
    };
    let (ga, gb) = (grid(a), grid(b));
    let both = ga.iter().zip(&gb).filter(|(x, y)| **x && **y).count() as f64;
    let larger = ga
        .iter()
        .filter(|x| **x)
        .count()
        .max(gb.iter().filter(|x| **x).count());
    if larger == 0 {
        return 0.0;
    }
    both / larger as f64
}

/// Joins thin parts of one material (`face_material`: one id per face, or empty when unknown)
/// stacked flat against each other into one part. Returns the new labels (numbered by smallest
/// face), their count and how many parts were joined to another.
#[must_use]
pub fn merge_layers(
    mesh: &TriMesh,
    face_part: &[u32],
    face_material: &[u32],
    options: &LayerOptions,
) -> (Vec<u32>, usize, usize) {
    let parts = PartFaces::of(mesh, face_part);
    let unchanged = || (face_part.to_vec(), parts.count(), 0);
    if parts.count() < 2 {
        return unchanged();
    }
    let diagonal_m = mesh.bounds().diagonal();
    let material = parts.main_materials(mesh, face_material);
    let mut sheets: Vec<Sheet> = (0..parts.count())
        .filter(|&p| parts.area_m2[p] >= options.area_fraction_min * parts.total_m2)
        .filter_map(|p| Sheet::of(mesh, p, &parts.faces_of[p], parts.area_m2[p], options))
        .collect();
    // The larger sheet of a pair gives the frame.
    sheets.sort_by(|a, b| b.area_m2.total_cmp(&a.area_m2));
    let mut stacked: Vec<(usize, usize)> = Vec::new();
    // The sides (along each sheet's normal) its stacked neighbours lie on.
    let mut sides: Vec<[bool; 2]> = vec![[false; 2]; sheets.len()];
    for (i, a) in sheets.iter().enumerate() {
        for (j, b) in sheets.iter().enumerate().skip(i + 1) {
            if material[a.part] != material[b.part]
                || a.shape.axes[2].dot(b.shape.axes[2]).abs() < options.parallel_cos_min
            {
                continue;
            }
            let length_m = a.shape.extents_m[0].max(b.shape.extents_m[0]);
            let stack = Stack::of(a, b, options.grid_cells);
            if stack.gap_m > options.gap_rel_max * diagonal_m
                || stack.thickness_m > options.stack_ratio_max * length_m
                || stack.cover < options.cover_min
            {
                continue;
            }
            stacked.push((i, j));
            if let Some(side) = side_of(b, a) {
                sides[i][usize::from(side)] = true;
            }
            if let Some(side) = side_of(a, b) {
                sides[j][usize::from(side)] = true;
            }
        }
    }
    let sandwiched = |s: usize| sides[s][0] && sides[s][1];
    let mut groups = UnionFind::new(parts.count());
    let mut group_m2 = parts.area_m2.clone();
    let mut joined = 0;
    for (i, j) in stacked {
        if sandwiched(i) || sandwiched(j) {
            continue;
        }
        let (ra, rb) = (
            groups.find(u32::try_from(sheets[i].part).unwrap_or(u32::MAX)),
            groups.find(u32::try_from(sheets[j].part).unwrap_or(u32::MAX)),
        );
        if ra == rb {
            continue;
        }
        let together_m2 = group_m2[ra as usize] + group_m2[rb as usize];
        if together_m2 >= options.whole_fraction_max * parts.total_m2 {
            continue;
        }
        groups.union(ra, rb);
        let root = groups.find(ra) as usize;
        group_m2[root] = together_m2;
        joined += 1;
    }
    if joined == 0 {
        return unchanged();
    }
    let labels: Vec<u32> = face_part.iter().map(|&p| groups.find(p)).collect();
    let (labels, count) = relabel_by_first_face(&labels);
    (labels, count, joined)
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;

    /// The boxes merged into one mesh, each its own part.
    fn parts(boxes: &[(DVec3, DVec3)]) -> (TriMesh, Vec<u32>) {
        let meshes: Vec<TriMesh> = boxes
            .iter()
            .map(|&(min, max)| TriMesh::cuboid(min, max))
            .collect();
        let mut labels = Vec::new();
        for (i, m) in meshes.iter().enumerate() {
            labels.extend(std::iter::repeat_n(i as u32, m.triangle_count()));
        }
        (TriMesh::merge(&meshes), labels)
    }

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn a_doors_skin_and_liner_join_and_the_cabinet_behind_stays() {
        let (mesh, labels) = parts(&[
            (v(0.0, 0.0, 0.0), v(1.0, 0.02, 1.0)),
            (v(0.05, 0.02, 0.05), v(0.95, 0.04, 0.95)),
            (v(0.0, 0.04, 0.0), v(1.0, 0.64, 1.0)),
        ]);
        let (joined, count, merged) = merge_layers(&mesh, &labels, &[], &LayerOptions::default());
        assert_eq!((count, merged), (2, 1));
        assert_eq!(joined[0], joined[12]);
        assert_ne!(joined[0], joined[24]);
        // A glass liner on a steel skin stays apart: every part is of one material.
        let materials: Vec<u32> = labels.iter().map(|&l| u32::from(l == 1)).collect();
        let (_, count, merged) = merge_layers(&mesh, &labels, &materials, &LayerOptions::default());
        assert_eq!((count, merged), (3, 0));
    }

    #[test]
    fn a_sheet_held_between_two_others_stays_and_the_outer_two_join() {
        let (mesh, labels) = parts(&[
            (v(0.0, 0.0, -0.035), v(1.0, 0.3, -0.005)),
            (v(0.0, 0.0, -0.005), v(1.0, 0.3, 0.005)),
            (v(0.0, 0.0, 0.005), v(1.0, 0.3, 0.035)),
        ]);
        let (joined, count, merged) = merge_layers(&mesh, &labels, &[], &LayerOptions::default());
        assert_eq!((count, merged), (2, 1));
        assert_eq!(joined[0], joined[24]);
        assert_ne!(joined[0], joined[12]);
    }

    #[test]
    fn stacked_bars_stay_apart_and_stacked_boards_as_long_join() {
        // Two bars of a linkage lying on each other (a tenth as wide as long), then the same
        // two a third as wide as long, with a body beside them.
        let body = (v(0.0, 0.5, 0.0), v(1.0, 1.1, 0.6));
        let stack = |width: f64| {
            parts(&[
                (v(0.0, 0.0, 0.0), v(1.0, width, 0.02)),
                (v(0.0, 0.0, 0.02), v(1.0, width, 0.04)),
                body,
            ])
        };
        let (mesh, labels) = stack(0.1);
        assert_eq!(
            merge_layers(&mesh, &labels, &[], &LayerOptions::default()).1,
            3
        );
        let (mesh, labels) = stack(0.33);
        assert_eq!(
            merge_layers(&mesh, &labels, &[], &LayerOptions::default()).1,
            2
        );
    }

    #[test]
    fn a_door_closed_on_a_face_frame_stays_apart_from_it() {
        // The frame (four bars around an opening) covers a third of what the door covers.
        let (mut mesh, mut labels) = parts(&[
            (v(0.0, 0.02, 0.0), v(1.0, 0.04, 0.1)),
            (v(0.0, 0.02, 0.9), v(1.0, 0.04, 1.0)),
            (v(0.0, 0.02, 0.1), v(0.1, 0.04, 0.9)),
            (v(0.9, 0.02, 0.1), v(1.0, 0.04, 0.9)),
            (v(0.0, 0.0, 0.0), v(1.0, 0.02, 1.0)),
            (v(0.0, 0.04, 0.0), v(1.0, 0.64, 1.0)),
        ]);
        for label in &mut labels {
            *label = label.saturating_sub(3);
        }
        let (joined, count, merged) = merge_layers(&mesh, &labels, &[], &LayerOptions::default());
        assert_eq!((count, merged), (3, 0));
        assert_eq!(joined, labels);
        // Without its opening the frame is a full board under the door, and they join.
        mesh = TriMesh::merge([
            &TriMesh::cuboid(v(0.0, 0.02, 0.0), v(1.0, 0.04, 1.0)),
            &TriMesh::cuboid(v(0.0, 0.0, 0.0), v(1.0, 0.02, 1.0)),
            &TriMesh::cuboid(v(0.0, 0.04, 0.0), v(1.0, 0.64, 1.0)),
        ]);
        labels = (0..36).map(|f| f / 12).collect();
        assert_eq!(
            merge_layers(&mesh, &labels, &[], &LayerOptions::default()).1,
            2
        );
    }

    #[test]
    fn a_closed_laptop_is_not_joined_into_one_part() {
        // The screen on the base is a stack, but the stack is the whole object.
        let (mesh, labels) = parts(&[
            (v(0.0, 0.0, 0.0), v(1.0, 0.7, 0.03)),
            (v(0.0, 0.0, 0.03), v(1.0, 0.7, 0.04)),
        ]);
        let (joined, count, merged) = merge_layers(&mesh, &labels, &[], &LayerOptions::default());
        assert_eq!((count, merged), (2, 0));
        assert_eq!(joined, labels);
    }
}
