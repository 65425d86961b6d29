//! How a moving part is held at rest, measured for the sweep: a turning axis against its parent
//! and its part, a short slide's gap to its parent, and the parent's surface normals where a
//! slide touches it (a face it presses into, walls that guide it). A long slide's slot is in
//! `slot`.

use uniphys_geometry::{Aabb, DMat3, DVec3, symmetric_eigen};
use uniphys_types::JointKind;

use crate::motion::JointMotion;
use crate::scene::Scene;
use crate::sweep_params::SweepParams;

/// Smallest and mean distance from a turning joint's axis line, over the stretch where it
/// passes the moving points, to the parent's surface (0 for other joints), metres.
pub(crate) fn hinge_to_parent_m(
    scene: &Scene,
    motion: &JointMotion,
    moving: &[DVec3],
    parent: usize,
) -> (f64, f64) {
    if !matches!(motion.kind, JointKind::Revolute | JointKind::Continuous) || moving.is_empty() {
        return (0.0, 0.0);
    }
    let axis = motion.axis_in_object;
    let pivot = motion.pivot_in_object_m;
    let (lo, hi) = moving
        .iter()
        .map(|p| (*p - pivot).dot(axis))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
            (lo.min(t), hi.max(t))
        });
    let distances: Vec<f64> = (0..=HINGE_SAMPLES)
        .map(|k| pivot + axis * (lo + (hi - lo) * k as f64 / HINGE_SAMPLES as f64))
        .map(|p| scene.surfaces.distance_m(parent, p))
        .collect();
    (
        distances.iter().copied().fold(f64::INFINITY, f64::min),
        distances.iter().sum::<f64>() / distances.len() as f64,
    )
}

/// The tensor (mean of `n n^T`) of the parent's triangle normals `n` where the `moving` samples
/// touch `parent` (within `touch_m`); `None` with fewer than 3 touching samples. Its largest
/// eigenvector is the normal of a face the part sits on, its smallest the axis of walls around
/// it.
pub(crate) fn contact_normal_tensor(
    scene: &Scene,
    parent: usize,
    moving: &[DVec3],
    touch_m: f64,
) -> Option<DMat3> {
    let normals: Vec<DVec3> = moving
        .iter()
        .filter_map(|p| scene.surfaces.nearest_normal(parent, *p, touch_m))
        .collect();
    (normals.len() >= 3).then(|| {
        normals.iter().fold(DMat3::ZERO, |t, n| {
            t + DMat3::from_cols(*n * n.x, *n * n.y, *n * n.z)
        }) * (1.0 / normals.len() as f64)
    })
}

/// The `points` within `touch_m` of `parent`'s surface.
pub(crate) fn touching_samples(
    scene: &Scene,
    parent: usize,
    points: &[DVec3],
    touch_m: f64,
) -> Vec<DVec3> {
    points
        .iter()
        .filter(|p| scene.surfaces.distance_m(parent, **p) <= touch_m)
        .copied()
        .collect()
}

/// How a slide along `axis` meets its contact normal tensor `T` ([`contact_normal_tensor`]):
/// how much it presses (`a^T T a` over `T`'s largest eigenvalue) and how much it is guided (the
/// smaller eigenvalue of `T` across the axis).
pub(crate) fn slide_against_contact(tensor: DMat3, axis: DVec3) -> (f64, f64) {
    let (values, _) = symmetric_eigen(tensor);
    let a = axis.normalize();
    let press = a.dot(tensor * a) / values.z.max(1e-12);
    let u = a.any_orthonormal_vector();
    let v = a.cross(u);
    let (uu, vv, uv) = (u.dot(tensor * u), v.dot(tensor * v), u.dot(tensor * v));
    let guidance = 0.5 * (uu + vv - ((uu - vv).powi(2) + 4.0 * uv * uv).sqrt());
    (press, guidance)
}

/// The distance within which a short slide's moving samples touch its parent at rest: the
/// contact distance at rest for the moving group (`rest_contact_part_fraction` of its
/// diagonal).
pub(crate) fn slide_touch_m(params: &SweepParams, moving: &[DVec3]) -> f64 {
    params.rest_contact_part_fraction * Aabb::from_points(moving).diagonal()
}

/// The distance within which moving samples touch another part at rest: `rest_contact_part_fraction`
/// of the moving group's diagonal (`group_diagonal_m`), at most `rest_contact_object_fraction`
/// of the object's (`object_diagonal_m`), metres.
pub(crate) fn rest_contact_m(
    params: &SweepParams,
    group_diagonal_m: f64,
    object_diagonal_m: f64,
) -> f64 {
    (params.rest_contact_part_fraction * group_diagonal_m)
        .min(params.rest_contact_object_fraction * object_diagonal_m)
}

/// The mean of `points` (zero for none).
pub(crate) fn mean(points: &[DVec3]) -> DVec3 {
    points.iter().sum::<DVec3>() / points.len().max(1) as f64
}

/// Distance from a joint's axis line to the nearest of `points`, metres.
pub(crate) fn line_to_points_m(motion: &JointMotion, points: &[DVec3]) -> f64 {
    points
        .iter()
        .map(|p| {
            (*p - motion.pivot_in_object_m)
                .reject_from_normalized(motion.axis_in_object)
                .length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Distance from the line through `on` along unit `axis` to the farthest of `points`, metres (a
/// part's reach from a hinge line); 0 without points.
pub(crate) fn farthest_from_line_m(points: &[DVec3], on: DVec3, axis: DVec3) -> f64 {
    points
        .iter()
        .map(|p| (*p - on).reject_from_normalized(axis).length())
        .fold(0.0, f64::max)
}

/// Points sampled along a hinge line.
const HINGE_SAMPLES: usize = 20;

/// The smallest distance from `points` (every fourth) to the surface of `parent`, metres.
pub(crate) fn gap_to_parent_m(scene: &Scene, parent: usize, points: &[DVec3]) -> f64 {
    scene
        .surfaces
        .nearest_distance_m(parent, points.iter().step_by(4).copied())
}
