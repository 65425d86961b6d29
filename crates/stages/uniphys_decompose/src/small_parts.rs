//! Small fragments merged into the part they touch (reference §3.6d, deterministic and with
//! thresholds relative to the object: no Monte-Carlo volume, no absolute distances).
//!
//! A part is small when its area is a tiny share of the surface, when it is tiny compared with
//! the object, when it is a small planar patch or when it is line-like. Each small part (smallest
//! first) joins the neighbour that the largest share of its surface samples touch (exact point to
//! triangle distances); without contact, the neighbour with the smallest box gap if it is near.
//! A somewhat larger part (below 2 % of the area) also joins a neighbour of the same material it
//! is clearly attached to when that neighbour is several times larger: handles and knobs go with
//! their drawer or lid (a steel handle on a wooden drawer stays a part of its own), unless it
//! is round about an axis (a wheel, a dial: [`crate::round`]) and so can spin against it
//! (the reference leaves that to PartField's features; a small separately moving button is the
//! price).

use uniphys_geometry::{Aabb, DVec3, TriMesh};

use crate::candidates::{UnionFind, relabel_by_first_face};
use crate::part_faces::main_materials;
use crate::round::is_round;

/// Tuning of [`merge_small_parts`]. Lengths are fractions of the bounds diagonal, areas of the
/// total surface area.
#[derive(Debug, Clone, PartialEq)]
pub struct SmallPartOptions {
    /// Parts below this share of the area are small. Default 0.001.
    pub area_fraction_min: f64,
    /// Parts whose largest extent is below this share of the diagonal are small. Default 0.03.
    pub extent_fraction_min: f64,
    /// Planar parts (thickness below 1e-4 of the diagonal) below this share of the area are
    /// small. Default 0.02.
    pub planar_area_fraction_max: f64,
    /// Parts above this share of the area are never merged. Default 0.1.
    pub area_fraction_keep: f64,
    /// A part below this share of the area that is attached to a much larger part (a handle on
    /// a drawer front, a knob on a lid) joins it. Default 0.02.
    pub attached_area_fraction_max: f64,
    /// ... attached meaning at least this share of its samples touch that part ... Default 0.1.
    pub attached_contact_min: f64,
    /// ... and that part has at least this many times its area. Default 4.
    pub attached_size_ratio: f64,
    /// Samples closer than this to a neighbour touch it. Default 0.005.
    pub contact_rel: f64,
    /// Neighbours farther (box gap) than this are not considered. Default 0.05.
    pub gap_rel: f64,
}

impl Default for SmallPartOptions {
    fn default() -> Self {
        Self {
            area_fraction_min: 0.001,
            extent_fraction_min: 0.03,
            planar_area_fraction_max: 0.02,
            area_fraction_keep: 0.1,
            attached_area_fraction_max: 0.02,
            attached_contact_min: 0.1,
            attached_size_ratio: 4.0,
            contact_rel: 0.005,
            gap_rel: 0.05,
        }
    }
}

/// Samples per small part (its vertices and face centres, evenly thinned).
const SAMPLES: usize = 200;

/// Merges small parts into their touching neighbours; returns the new labels (numbered by
/// smallest face), their count and how many parts were merged away.
#[must_use]
pub fn merge_small_parts(
    mesh: &TriMesh,
    face_part: &[u32],
    face_material: &[u32],
    options: &SmallPartOptions,
) -> (Vec<u32>, usize, usize) {
    let parts = face_part.iter().max().map_or(0, |&m| m as usize + 1);
    let bounds = mesh.bounds();
    let diagonal = bounds.diagonal();
    let total_area = mesh.area();
    if parts <= 1 || diagonal <= 0.0 || total_area <= 0.0 {
        let (labels, count) = relabel_by_first_face(face_part);
        return (labels, count, 0);
    }
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); parts];
    for (f, &p) in face_part.iter().enumerate() {
        faces_of[p as usize].push(f);
    }
    let area: Vec<f64> = faces_of
        .iter()
        .map(|fs| fs.iter().map(|&f| mesh.face_area(f)).sum())
        .collect();
    let boxes: Vec<Aabb> = faces_of
        .iter()
        .map(|fs| {
            fs.iter()
                .flat_map(|&f| mesh.corners(f))
                .fold(Aabb::EMPTY, Aabb::grown)
        })
        .collect();
    // Material covering most of each part's area (smallest id on ties).
    let material = main_materials(mesh, &faces_of, face_material);
    let is_small = |p: usize| -> bool {
        let share = area[p] / total_area;
        if share > options.area_fraction_keep {
            return false;
        }
        let mut e = boxes[p].extents().to_array();
        e.sort_by(f64::total_cmp);
        share < options.area_fraction_min
            || e[2] < options.extent_fraction_min * diagonal
            || (e[0] < 1e-4 * diagonal && share < options.planar_area_fraction_max)
            || e[1] < 1e-3 * diagonal
    };
    let may_be_attached = |p: usize| area[p] < options.attached_area_fraction_max * total_area;
    let mut order: Vec<usize> = (0..parts)
        .filter(|&p| is_small(p) || may_be_attached(p))
        .collect();
    order.sort_by(|&a, &b| area[a].total_cmp(&area[b]).then(a.cmp(&b)));
    let contact_m = options.contact_rel * diagonal;
    let gap_m = options.gap_rel * diagonal;
    let mut groups = UnionFind::new(parts);
    let mut merged = 0;
    for &p in &order {
        let samples = samples(mesh, &faces_of[p]);
        let mut best: Option<(f64, f64, usize)> = None; // (contact share, -gap, part)
        for q in 0..parts {
            if q == p
                || groups.find(u32::try_from(q).unwrap_or(0))
                    == groups.find(u32::try_from(p).unwrap_or(0))
            {
                continue;
            }
            let gap = box_gap(&boxes[p], &boxes[q]);
            if gap > gap_m {
                continue;
            }
            let share = contact_share(mesh, &samples, &faces_of[q], &boxes[p], contact_m);
            let key = (share, -gap, q);
            if best.is_none_or(|b| key.0 > b.0 || (key.0 == b.0 && key.1 > b.1)) {
                best = Some(key);
            }
        }
        let Some((share, _, q)) = best else {
            continue;
        };
        let attached = share >= options.attached_contact_min
            && area[q] >= options.attached_size_ratio * area[p]
            && material[p] == material[q]
            && !is_round(mesh, &faces_of[p]);
        if is_small(p) || attached {
            groups.union(u32::try_from(p).unwrap_or(0), u32::try_from(q).unwrap_or(0));
            merged += 1;
        }
    }
    let labels: Vec<u32> = face_part.iter().map(|&p| groups.find(p)).collect();
    let (labels, count) = relabel_by_first_face(&labels);
    (labels, count, merged)
}

/// Up to [`SAMPLES`] points of the faces: vertices and face centres, evenly thinned.
pub(crate) fn samples(mesh: &TriMesh, faces: &[usize]) -> Vec<DVec3> {
    let mut points: Vec<DVec3> = Vec::with_capacity(faces.len() * 4);
    for &f in faces {
        let c = mesh.corners(f);
        points.extend(c);
        points.push((c[0] + c[1] + c[2]) / 3.0);
    }
    let stride = points.len().div_ceil(SAMPLES).max(1);
    points.into_iter().step_by(stride).collect()
}

/// Share of `samples` within `contact_m` of the faces of another part (only faces near the
/// samples' box are tested).
fn contact_share(
    mesh: &TriMesh,
    samples: &[DVec3],
    faces: &[usize],
    near: &Aabb,
    contact_m: f64,
) -> f64 {
    let grown = Aabb {
        min: near.min - DVec3::splat(contact_m),
        max: near.max + DVec3::splat(contact_m),
    };
    let close: Vec<[DVec3; 3]> = faces
        .iter()
        .map(|&f| mesh.corners(f))
        .filter(|c| box_gap(&Aabb::from_points(c.iter()), &grown) <= 0.0)
        .collect();
    if close.is_empty() || samples.is_empty() {
        return 0.0;
    }
    let limit2 = contact_m * contact_m;
    let touching = samples
        .iter()
        .filter(|&&s| {
            close
                .iter()
                .any(|t| closest_on_triangle(s, t).distance_squared(s) <= limit2)
        })
        .count();
    touching as f64 / samples.len() as f64
}

/// Distance between two boxes (0 when they overlap).
fn box_gap(a: &Aabb, b: &Aabb) -> f64 {
    (a.min - b.max).max(b.min - a.max).max(DVec3::ZERO).length()
}

/// The point of triangle `t` closest to `p` (Voronoi regions of the vertices, edges and face).
pub(crate) fn closest_on_triangle(p: DVec3, t: &[DVec3; 3]) -> DVec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom.abs() < f64::MIN_POSITIVE {
        return a;
    }
    a + ab * (vb / denom) + ac * (vc / denom)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_on_a_triangle_in_each_region() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let inside = closest_on_triangle(DVec3::new(0.2, 0.2, 1.0), &t);
        assert!((inside - DVec3::new(0.2, 0.2, 0.0)).length() < 1e-12);
        assert_eq!(
            closest_on_triangle(DVec3::new(-1.0, -1.0, 0.0), &t),
            DVec3::ZERO
        );
        assert_eq!(
            closest_on_triangle(DVec3::new(0.5, -2.0, 0.0), &t),
            DVec3::new(0.5, 0.0, 0.0)
        );
        let on_hyp = closest_on_triangle(DVec3::new(1.0, 1.0, 0.0), &t);
        assert!((on_hyp - DVec3::new(0.5, 0.5, 0.0)).length() < 1e-12);
    }

    #[test]
    fn a_knob_joins_the_drawer_it_touches_not_the_nearby_body() {
        // Body, a drawer front in front of it (touching), a small knob on the drawer front.
        let body = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 1.0));
        let drawer = TriMesh::cuboid(DVec3::new(0.1, -0.05, 0.1), DVec3::new(0.9, 0.0, 0.5));
        let knob = TriMesh::cuboid(DVec3::new(0.48, -0.07, 0.28), DVec3::new(0.52, -0.05, 0.32));
        let mesh = TriMesh::merge([&body, &drawer, &knob]);
        let labels: Vec<u32> = (0..36).map(|f| (f / 12) as u32).collect();
        let (merged, count, moved) =
            merge_small_parts(&mesh, &labels, &[], &SmallPartOptions::default());
        assert_eq!((count, moved), (2, 1));
        let expected: Vec<u32> = (0..36).map(|f| u32::from(f >= 12)).collect();
        assert_eq!(merged, expected);
    }

    #[test]
    fn an_attached_handle_joins_a_drawer_of_its_material_only() {
        // Drawer front with a handle of 1 % of the area (not tiny, but attached).
        let drawer = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.1, 1.0));
        let handle = TriMesh::cuboid(DVec3::new(0.4, -0.02, 0.48), DVec3::new(0.6, 0.0, 0.52));
        let mesh = TriMesh::merge([&drawer, &handle]);
        let labels: Vec<u32> = (0..24).map(|f| u32::from(f >= 12)).collect();
        let share = (12..24).map(|f| mesh.face_area(f)).sum::<f64>() / mesh.area();
        assert!(share > 0.005 && share < 0.02, "{share}");
        let options = SmallPartOptions::default();
        let same = merge_small_parts(&mesh, &labels, &[0; 24], &options);
        assert_eq!((same.1, same.2), (1, 1));
        let steel: Vec<u32> = (0..24).map(|f| u32::from(f >= 12)).collect();
        let different = merge_small_parts(&mesh, &labels, &steel, &options);
        assert_eq!((different.1, different.2), (2, 0));
    }

    #[test]
    fn a_small_part_far_from_everything_stays() {
        let body = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let speck = TriMesh::cuboid(DVec3::splat(3.0), DVec3::splat(3.01));
        let mesh = TriMesh::merge([&body, &speck]);
        let labels: Vec<u32> = (0..24).map(|f| u32::from(f >= 12)).collect();
        let (merged, count, moved) =
            merge_small_parts(&mesh, &labels, &[], &SmallPartOptions::default());
        assert_eq!((count, moved), (2, 0));
        assert_eq!(merged, labels);
    }
}
