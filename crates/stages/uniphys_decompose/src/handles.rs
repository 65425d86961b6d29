//! A panel that carries a handle is a door or a drawer front: it moves, so the merge of parts the
//! views show together must not join it to the body.
//!
//! Why: flush doors and drawer fronts are one region in every view of the built-in segmenter (no
//! gap of a pixel, no concave crease), so the merge joins them to the body; and whether a part
//! can move does not tell them from the body's own panels (on the shared PartNet-Mobility
//! objects, all 164 parts the merge joined that had surface clear of the rest, rigid or not,
//! had a hinge along an edge of their box or a slide free of collision). A handle does: a small
//! piece standing off the panel's outer face (the side away from the object's centre), over the
//! panel's outline and touching it, on a face that does not look down (what stands under an
//! object is a foot) and that no larger piece covers (an inner panel behind a door). A panel
//! with more such pieces than a door carries (a keyboard's keys, a grille's bars) is not taken
//! for a door.

use uniphys_geometry::{Aabb, DVec3, TriMesh, principal_axes, projection_range};

use crate::candidates::relabel_by_first_face;
use crate::pieces::mesh_pieces;
use crate::small_parts::samples;

/// Tuning of [`keep_handled_panels`]. Areas are shares of the total surface area, lengths of
/// the bounds diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct HandleOptions {
    /// Whether the step runs. Default true.
    pub enabled: bool,
    /// A panel is at most this thick for its length. Default 0.2.
    pub panel_thickness_ratio_max: f64,
    /// A handle holds at most this share of the surface ... Default 0.01.
    pub handle_area_fraction_max: f64,
    /// ... and at least this share (not dust). Default 1e-5.
    pub handle_area_fraction_min: f64,
    /// ... its nearest point is at most this far off the panel's outer face ... Default 0.01.
    pub touch_rel: f64,
    /// ... and its farthest at least this far. Default 0.005.
    pub standoff_rel: f64,
    /// A panel standing more pieces than this off its face is a keyboard or a grille. Default 2.
    pub handles_max: usize,
}

impl Default for HandleOptions {
    fn default() -> Self {
        Self {
            enabled: true,
            panel_thickness_ratio_max: 0.2,
            handle_area_fraction_max: 0.01,
            handle_area_fraction_min: 1e-5,
            touch_rel: 0.01,
            standoff_rel: 0.005,
            handles_max: 2,
        }
    }
}

/// Share of a handle's samples that lie over the panel (inside its outline) ...
const OVER_PANEL_SHARE: f64 = 0.9;
/// ... and on the outer side of its face.
const OUTSIDE_SHARE: f64 = 0.9;
/// A larger piece with this share of its samples over the panel, beyond its face, covers it.
const COVER_SHARE: f64 = 0.5;
/// A panel whose outer face looks down within 45 degrees is an underside: its studs are feet.
const UNDERSIDE_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Splits every part of `refined` that the merge (`merged`) joined to others and that carries a
/// handle back out of its group, together with its handles. Returns the labels (numbered by
/// smallest face), their count and the number of panels kept apart.
#[must_use]
pub fn keep_handled_panels(
    mesh: &TriMesh,
    refined: &[u32],
    merged: &[u32],
    options: &HandleOptions,
) -> (Vec<u32>, usize, usize) {
    let (labels, count) = relabel_by_first_face(merged);
    if !options.enabled {
        return (labels, count, 0);
    }
    let parts = refined.iter().max().map_or(0, |&m| m as usize + 1);
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); parts];
    for (f, &p) in refined.iter().enumerate() {
        faces_of[p as usize].push(f);
    }
    // Refined parts per merged group: only parts that were joined to others are looked at.
    let mut members = vec![0usize; count];
    for faces in faces_of.iter().filter(|f| !f.is_empty()) {
        members[labels[faces[0]] as usize] += 1;
    }
    if members.iter().all(|&m| m < 2) {
        return (labels, count, 0);
    }
    let scene = Scene::of(mesh);
    let mut out = labels.clone();
    let mut next = u32::try_from(count).unwrap_or(u32::MAX);
    let mut kept = 0;
    for faces in &faces_of {
        let Some(&first) = faces.first() else {
            continue;
        };
        if members[labels[first] as usize] < 2 {
            continue;
        }
        let Some(handles) = scene.handles_of(mesh, faces, options) else {
            continue;
        };
        for &f in faces
            .iter()
            .chain(handles.iter().flat_map(|&q| &scene.faces_of[q]))
        {
            out[f] = next;
        }
        next += 1;
        kept += 1;
    }
    let (out, count) = relabel_by_first_face(&out);
    (out, count, kept)
}

/// What every test needs once: the mesh's pieces, their faces, areas and boxes.
struct Scene {
    piece: Vec<u32>,
    faces_of: Vec<Vec<usize>>,
    piece_area_m2: Vec<f64>,
    piece_bounds: Vec<Aabb>,
    total_m2: f64,
    diagonal_m: f64,
    centre: DVec3,
}

impl Scene {
    fn of(mesh: &TriMesh) -> Self {
        let (piece, pieces) = mesh_pieces(mesh);
        let mut faces_of = vec![Vec::new(); pieces];
        let mut piece_area_m2 = vec![0.0f64; pieces];
        let mut piece_bounds = vec![Aabb::EMPTY; pieces];
        for (f, &q) in piece.iter().enumerate() {
            let q = q as usize;
            faces_of[q].push(f);
            piece_area_m2[q] += mesh.face_area(f);
            for corner in mesh.corners(f) {
                piece_bounds[q] = piece_bounds[q].grown(corner);
            }
        }
        let bounds = mesh.bounds();
        Self {
            piece,
            faces_of,
            total_m2: piece_area_m2.iter().sum(),
            piece_area_m2,
            piece_bounds,
            diagonal_m: bounds.diagonal(),
            centre: bounds.center(),
        }
    }

    /// The pieces standing as handles on the part made of `faces` (its largest piece is the
    /// panel), or `None` when it is no panel or carries none or too many.
    fn handles_of(
        &self,
        mesh: &TriMesh,
        faces: &[usize],
        options: &HandleOptions,
    ) -> Option<Vec<usize>> {
        let mut area_in = std::collections::BTreeMap::<u32, f64>::new();
        for &f in faces {
            *area_in.entry(self.piece[f]).or_default() += mesh.face_area(f);
        }
        let main = area_in
            .iter()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(&q, _)| q)?;
        let panel_faces: Vec<usize> = faces
            .iter()
            .copied()
            .filter(|&f| self.piece[f] == main)
            .collect();
        let panel = Panel::of(mesh, &panel_faces, self.centre)?;
        // What stands under the face an object rests on is a foot, not a handle (Z-up frame).
        if panel.thickness_ratio() > options.panel_thickness_ratio_max
            || panel.axes[2].z < -UNDERSIDE_COS
        {
            return None;
        }
        let touch_m = options.touch_rel * self.diagonal_m;
        let standoff_m = options.standoff_rel * self.diagonal_m;
        let clear_m = 0.1 * (panel.extent(2) + 1e-3 * self.diagonal_m);
        let handles: Vec<usize> = (0..self.faces_of.len())
            .filter(|&q| {
                let share = self.piece_area_m2[q] / self.total_m2;
                q != main as usize
                    && share <= options.handle_area_fraction_max
                    && share >= options.handle_area_fraction_min
                    && panel.near_box(self.piece_bounds[q], touch_m)
                    && panel.stands_on(
                        &samples(mesh, &self.faces_of[q]),
                        touch_m,
                        clear_m,
                        standoff_m,
                    )
            })
            .collect();
        if handles.is_empty() || handles.len() > options.handles_max {
            return None;
        }
        // A larger piece standing over the panel covers it: an inner panel behind a door, whose
        // "handle" is the door's.
        let covered = (0..self.faces_of.len()).any(|q| {
            q != main as usize
                && self.piece_area_m2[q] / self.total_m2 > options.handle_area_fraction_max
                && panel.covered_by(&samples(mesh, &self.faces_of[q]), clear_m)
        });
        (!covered).then_some(handles)
    }
}

/// A thin panel: its principal axes (the last is its normal, pointing away from the object's
/// centre) and its ranges along them.
struct Panel {
    axes: [DVec3; 3],
    ranges: [(f64, f64); 3],
    bounds: Aabb,
}

impl Panel {
    fn of(mesh: &TriMesh, faces: &[usize], object_centre: DVec3) -> Option<Self> {
        let points = samples(mesh, faces);
        if points.len() < 3 {
            return None;
        }
        let mut axes = principal_axes(&points);
        let mean = points.iter().sum::<DVec3>() / points.len() as f64;
        let outward = (mean - object_centre).dot(axes[2]);
        if outward == 0.0 {
            return None;
        }
        if outward < 0.0 {
            axes[2] = -axes[2];
        }
        let ranges = axes.map(|a| projection_range(&points, a));
        let bounds = Aabb::from_points(&points);
        Some(Self {
            axes,
            ranges,
            bounds,
        })
    }

    fn extent(&self, axis: usize) -> f64 {
        self.ranges[axis].1 - self.ranges[axis].0
    }

    fn thickness_ratio(&self) -> f64 {
        let length = self.extent(0);
        if length > 0.0 {
            self.extent(2) / length
        } else {
            f64::INFINITY
        }
    }

    /// Whether a box comes within `margin_m` of the panel's box.
    fn near_box(&self, other: Aabb, margin_m: f64) -> bool {
        let grow = DVec3::splat(margin_m);
        (other.min - grow).cmple(self.bounds.max).all()
            && (other.max + grow).cmpge(self.bounds.min).all()
    }

    /// Whether at least half of `points` lie over the panel's outline, beyond its outer face by
    /// `clear_m`.
    fn covered_by(&self, points: &[DVec3], clear_m: f64) -> bool {
        let over = points
            .iter()
            .filter(|p| self.over_outline(**p) && p.dot(self.axes[2]) - self.ranges[2].1 > clear_m)
            .count();
        !points.is_empty() && over as f64 >= COVER_SHARE * points.len() as f64
    }

    fn over_outline(&self, p: DVec3) -> bool {
        (0..2).all(|k| {
            let x = p.dot(self.axes[k]);
            x >= self.ranges[k].0 && x <= self.ranges[k].1
        })
    }

    /// Whether `points` stand on the outer face: over the panel's outline, none sunk behind
    /// the face by more than `clear_m`, the nearest within `touch_m` of it and the farthest at
    /// least `standoff_m` off it.
    fn stands_on(&self, points: &[DVec3], touch_m: f64, clear_m: f64, standoff_m: f64) -> bool {
        if points.is_empty() {
            return false;
        }
        let face = self.ranges[2].1;
        let mut over = 0usize;
        let mut outside = 0usize;
        let (mut lowest, mut highest) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in points {
            over += usize::from(self.over_outline(*p));
            let height = p.dot(self.axes[2]) - face;
            outside += usize::from(height >= -clear_m);
            lowest = lowest.min(height);
            highest = highest.max(height);
        }
        let n = points.len() as f64;
        over as f64 >= OVER_PANEL_SHARE * n
            && outside as f64 >= OUTSIDE_SHARE * n
            && lowest <= touch_m
            && highest >= standoff_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::test_meshes::{CUBOID_FACES, boxes};

    /// `parts` as boxes merged into one mesh, with the part of every face.
    fn labelled(parts: &[(DVec3, DVec3)]) -> (TriMesh, Vec<u32>) {
        let refined = (0..parts.len())
            .flat_map(|p| std::iter::repeat_n(u32::try_from(p).unwrap(), CUBOID_FACES))
            .collect();
        (boxes(parts), refined)
    }

    /// A cabinet body (a box) with a door panel on its front (+x) and, optionally, a bar handle
    /// on the door; the merge joined everything into one part. Each box is 12 faces.
    fn cabinet(handle: bool) -> (TriMesh, Vec<u32>) {
        let mut parts = vec![
            (DVec3::ZERO, DVec3::new(0.5, 0.6, 1.0)),
            (DVec3::new(0.5, 0.02, 0.02), DVec3::new(0.52, 0.58, 0.98)),
        ];
        if handle {
            parts.push((DVec3::new(0.52, 0.5, 0.4), DVec3::new(0.55, 0.53, 0.6)));
        }
        labelled(&parts)
    }

    #[test]
    fn a_door_with_a_handle_is_split_out_of_the_body_with_its_handle() {
        let (mesh, refined) = cabinet(true);
        let merged = vec![0u32; refined.len()];
        let (labels, count, kept) =
            keep_handled_panels(&mesh, &refined, &merged, &HandleOptions::default());
        assert_eq!((count, kept), (2, 1), "{labels:?}");
        assert!(labels[..12].iter().all(|&l| l == 0));
        assert!(labels[12..].iter().all(|&l| l == 1));
    }

    #[test]
    fn a_panel_without_a_handle_or_with_many_studs_stays_merged() {
        let (mesh, refined) = cabinet(false);
        let merged = vec![0u32; refined.len()];
        let (_, count, kept) =
            keep_handled_panels(&mesh, &refined, &merged, &HandleOptions::default());
        assert_eq!((count, kept), (1, 0));
        // Three studs on the door are surface detail, not a handle.
        let mut parts = vec![
            (DVec3::ZERO, DVec3::new(0.5, 0.6, 1.0)),
            (DVec3::new(0.5, 0.02, 0.02), DVec3::new(0.52, 0.58, 0.98)),
        ];
        for z in [0.2, 0.5, 0.8] {
            parts.push((DVec3::new(0.52, 0.3, z), DVec3::new(0.54, 0.32, z + 0.02)));
        }
        let (mesh, refined) = labelled(&parts);
        let (_, count, kept) = keep_handled_panels(
            &mesh,
            &refined,
            &vec![0u32; refined.len()],
            &HandleOptions::default(),
        );
        assert_eq!((count, kept), (1, 0));
    }

    #[test]
    fn a_door_left_alone_by_the_merge_is_not_touched() {
        let (mesh, refined) = cabinet(true);
        // The merge kept the body, the door and the handle apart.
        let (labels, count, kept) =
            keep_handled_panels(&mesh, &refined, &refined, &HandleOptions::default());
        assert_eq!((count, kept), (3, 0));
        assert_eq!(labels, refined);
    }
}
