//! How a moving part is held at rest, measured for the sweep: a turning axis against its parent
//! and its part, a short slide's gap to its parent, and the parent's surface normals where a
//! slide touches it (a face it presses into, walls that guide it). A long slide's slot is in
//! `slot`.

use uniphys_geometry::{Aabb, DMat3, DVec3, symmetric_eigen};
use uniphys_types::JointKind;

use crate::motion::JointMotion;
use crate::scene::Scene;
use crate::sweep_params::SweepParams;

/// A turning joint's axis line against its parent, over the stretch where it passes the moving
/// points (all 0 for other joints), metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HingeToParent {
    /// Smallest distance from the line to the parent's surface.
    pub(crate) min_m: f64,
    /// Mean distance from the line to the parent's surface.
    pub(crate) mean_m: f64,
    /// Mean distance to the parent's surface along the stretch, leaving out where the line
    /// crosses open space between two points where it runs through the moving parts (its pin
    /// spans a gap: a bucket's handle is held at its two ends, not across the bucket's opening);
    /// the mean over the whole stretch when the line runs through them nowhere.
    pub(crate) pin_mean_m: f64,
}

/// A line point this close to the moving parts, as a share of their diagonal, runs through them.
const PIN_IN_PART_FRACTION: f64 = 0.05;

/// How a turning joint's axis line lies against the parent's surface ([`HingeToParent`]); the
/// moving group is `moving_parts`, sampled at `moving`, whose box has diagonal `diagonal_m`.
pub(crate) fn hinge_to_parent_m(
    scene: &Scene,
    motion: &JointMotion,
    (moving_parts, moving, diagonal_m): (&[usize], &[DVec3], f64),
    parent: usize,
) -> HingeToParent {
    if !matches!(motion.kind, JointKind::Revolute | JointKind::Continuous) || moving.is_empty() {
        return HingeToParent {
            min_m: 0.0,
            mean_m: 0.0,
            pin_mean_m: 0.0,
        };
    }
    let axis = motion.axis_in_object;
    let pivot = motion.pivot_in_object_m;
    let (lo, hi) = moving
        .iter()
        .map(|p| (*p - pivot).dot(axis))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
            (lo.min(t), hi.max(t))
        });
    let line: Vec<DVec3> = (0..=HINGE_SAMPLES)
        .map(|k| pivot + axis * (lo + (hi - lo) * k as f64 / HINGE_SAMPLES as f64))
        .collect();
    let distances: Vec<f64> = line
        .iter()
        .map(|p| scene.surfaces.distance_m(parent, *p))
        .collect();
    let mean_m = distances.iter().sum::<f64>() / distances.len() as f64;
    let in_part_m = PIN_IN_PART_FRACTION * diagonal_m;
    let in_part: Vec<bool> = line
        .iter()
        .map(|p| {
            moving_parts
                .iter()
                .any(|&m| scene.surfaces.distance_m(m, *p) <= in_part_m)
        })
        .collect();
    // Between the first and the last point in the part, the line may cross open space (a
    // bucket's opening between the handle's two ends); beyond them it is judged all along (a
    // line that leaves a lever's stem sideways is held nowhere up there).
    let first = in_part.iter().position(|&b| b);
    let last = in_part.iter().rposition(|&b| b);
    let pin_mean_m = match (first, last) {
        (Some(first), Some(last)) => {
            let held: Vec<f64> = distances
                .iter()
                .enumerate()
                .filter(|&(k, _)| in_part[k] || k < first || k > last)
                .map(|(_, d)| *d)
                .collect();
            held.iter().sum::<f64>() / held.len() as f64
        }
        _ => mean_m,
    };
    HingeToParent {
        min_m: distances.iter().copied().fold(f64::INFINITY, f64::min),
        mean_m,
        pin_mean_m,
    }
}

/// A moving sample within touch distance of its parent at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Touch {
    /// The sample.
    pub(crate) sample: DVec3,
    /// The point of the parent's surface nearest to it.
    pub(crate) nearest: DVec3,
    /// The unit normal of the parent's triangle there, as the triangle is wound.
    pub(crate) normal: DVec3,
}

/// The `moving` samples within `touch_m` of `parent`'s surface, each with the nearest point of
/// that surface and its triangle's normal.
pub(crate) fn touches(scene: &Scene, parent: usize, moving: &[DVec3], touch_m: f64) -> Vec<Touch> {
    moving
        .iter()
        .filter_map(|p| {
            let (nearest, normal) = scene.surfaces.nearest_with_normal(parent, *p, touch_m)?;
            Some(Touch {
                sample: *p,
                nearest,
                normal,
            })
        })
        .collect()
}

/// The tensor (mean of `n n^T`) of the parent's triangle normals `n` where moving samples touch
/// it ([`touches`]); `None` with fewer than 3 touching samples. Its largest eigenvector is the
/// normal of a face the part sits on, its smallest the axis of walls around it.
pub(crate) fn contact_normal_tensor(touches: &[Touch]) -> Option<DMat3> {
    (touches.len() >= 3).then(|| {
        touches.iter().fold(DMat3::ZERO, |t, touch| {
            let n = touch.normal;
            t + DMat3::from_cols(n * n.x, n * n.y, n * n.z)
        }) * (1.0 / touches.len() as f64)
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
