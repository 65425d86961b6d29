//! How well a motion that passed its sweep fits the part it moves, comparable across
//! corrections that change different things (the range, the pivot, the axis, the kind). A sweep
//! only says a motion is possible; several wrong ones often are (a door swung as a flap about
//! its bottom edge, a laptop screen turned about its side edge, a knob flipped about a line
//! across it). What tells the intended one apart is how real mechanisms are built:
//! - a hinge runs along the part it is attached to (its pin sits in the parent's frame, or
//!   spans the gap between two holds, as a bucket's handle's does);
//! - a panel's handle sits far from its hinge, where pulling turns the panel most easily;
//! - a part that spins in place (a knob, a wheel, a cap) is round about its axis: turned, it
//!   lands on itself.

use std::f64::consts::PI;

use uniphys_geometry::{Aabb, DQuat, DVec3, KdTree};
use uniphys_types::{Joint, JointKind};

use crate::handle::handled_panel_spun;
use crate::held::{farthest_from_line_m, mean};
use crate::scene::Scene;
use crate::sweep::SweepMetrics;

/// A revolute joint whose range exceeds this may spin in place (a knob turned 330 degrees): the
/// line its part is round about is tried as a correction. One limited to less turns its part
/// part-way, which moves nothing when the part is round about the line (`sweep`).
pub(crate) const SPIN_RANGE_MIN_RAD: f64 = PI;
/// Angles the part is turned by to measure its roundness about an axis.
const SPIN_ANGLES_RAD: [f64; 5] = [PI / 3.0, 2.0 * PI / 3.0, PI, 4.0 * PI / 3.0, 5.0 * PI / 3.0];
/// Most samples turned per angle (every k-th of the part's).
const SPIN_SAMPLES_MAX: usize = 400;
/// Weight of the roundness residual (a share of the part's diagonal) against the hinge terms: a
/// knob flipped about a line across it lands about a tenth of its diagonal from itself.
const SPIN_WEIGHT: f64 = 5.0;

/// How badly a passing `joint` (its sweep: `metrics`) fits the parts it moves (sampled at
/// `moving`), 0 for a perfect fit, about 1 for a clear misfit:
/// - a hinge: its mean distance from the parent along the stretch where it passes the part
///   (leaving out open space its pin spans between two holds, as a bucket's handle's does), a
///   share of the moving parts' width across the axis ([`width_across_m`]), plus how far the
///   panel's handle is from the far edge (1 minus its share of the reach, when there is a
///   handle; 1 when a panel with a handle would spin in its own plane);
/// - a spin (continuous): the roundness residual ([`spin_residual`]) times 5; a revolute joint
///   over half a turn ([`may_spin`]) is judged both ways and keeps the better fit (a knob with a
///   stop spins, a bucket's handle swings);
/// - a slide: the share of its sweep it spends out of contact with its parent (a drawer runs on
///   its frame to the end of its travel; a door, a lid or a screen slid off its frame is held by
///   nothing), plus how far it runs askew of every direction it could be built along
///   ([`slide_skew`]: a door slid diagonally across the face it closes).
pub(crate) fn misfit(
    scene: &Scene,
    joint: &Joint,
    moving_parts: &[usize],
    moving: &[DVec3],
    metrics: &SweepMetrics,
) -> f64 {
    let axis = DVec3::from_array(joint.axis_in_object).normalize_or_zero();
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    if spins(joint) {
        return SPIN_WEIGHT * spin_residual(moving, axis, pivot);
    }
    match joint.kind {
        JointKind::Revolute => {}
        JointKind::Prismatic => {
            let lost = metrics.lost_contact_steps as f64 / metrics.steps.max(1) as f64;
            return lost + slide_skew(scene, joint, moving_parts, moving, axis);
        }
        JointKind::Continuous | JointKind::Fixed => return 0.0,
    }
    let along = (metrics.hinge_pin_to_parent_m / width_across_m(moving, axis)).min(1.0);
    let handle = match metrics.handle_reach_fraction {
        Some(f) => (1.0 - f).clamp(0.0, 1.0),
        None => {
            let child = &scene.samples[joint.child.0 as usize];
            let away = mean(moving) - mean(&scene.samples[joint.parent.0 as usize]);
            if handled_panel_spun(child, moving, axis, away) {
                1.0
            } else {
                0.0
            }
        }
    };
    let hinge = along + handle;
    if may_spin(joint) {
        // A knob turned 330 degrees spins in place as well as any continuous one; its grip ridge
        // would otherwise count as a handle on a panel spun in its own plane.
        hinge.min(SPIN_WEIGHT * spin_residual(moving, axis, pivot))
    } else {
        hinge
    }
}

/// A slide within this angle of a direction it could be built along runs along it, radians (15
/// degrees: a part's box leans a few degrees with its handle or grip).
const SLIDE_SQUARE_RAD: f64 = 0.26;
/// A slide this much further askew fits as badly as one that leaves its parent at once, radians
/// (30 degrees: at 45 degrees a slide is as far as it can be from two square directions).
const SLIDE_SKEW_SPAN_RAD: f64 = 0.52;

/// How far a slide along unit `axis` runs askew of the directions real slides are built along:
/// the edges of the moving parts' box (`moving_parts`, sampled at `moving`: a drawer, a button
/// pushed along its own axis, a sliding door), of its parent's (a runner, a slot), and the
/// vertical of an object on the ground (a lid lifted). 0 within [`SLIDE_SQUARE_RAD`] of one,
/// rising to 1 over [`SLIDE_SKEW_SPAN_RAD`] more. The boxes are the scene's, found once.
fn slide_skew(
    scene: &Scene,
    joint: &Joint,
    moving_parts: &[usize],
    moving: &[DVec3],
    axis: DVec3,
) -> f64 {
    if axis == DVec3::ZERO || moving.is_empty() {
        return 0.0;
    }
    let mut square: Vec<DVec3> = scene.part_box(moving_parts, moving).axes.to_vec();
    let parent = [joint.parent.0 as usize];
    let parent_points = &scene.samples[parent[0]];
    if !parent_points.is_empty() {
        square.extend(scene.part_box(&parent, parent_points).axes);
    }
    if scene.ground_z_m.is_some() {
        square.push(DVec3::Z);
    }
    let skew = square
        .iter()
        .map(|d| d.dot(axis).abs().clamp(0.0, 1.0).acos())
        .fold(f64::INFINITY, f64::min);
    ((skew - SLIDE_SQUARE_RAD) / SLIDE_SKEW_SPAN_RAD).clamp(0.0, 1.0)
}

/// The width of a part (sampled at `points`) across a unit `axis`: twice the largest distance of
/// a sample from the line along the axis through their centroid. A hinge's offset from its
/// parent is judged against it, the size of the part in the plane it turns in (a tall door's
/// width, not its diagonal, which its height inflates).
fn width_across_m(points: &[DVec3], axis: DVec3) -> f64 {
    (2.0 * farthest_from_line_m(points, mean(points), axis)).max(1e-12)
}

/// A turning joint judged by its roundness: a continuous one, which spins in place (a knob, a
/// wheel, a cap). A revolute joint is judged as a hinge whatever its range (a bucket's handle
/// swings over 260 degrees and is not round).
pub(crate) fn spins(joint: &Joint) -> bool {
    joint.kind == JointKind::Continuous
}

/// A turning joint that may spin in place, so the line its part is round about is worth
/// trying: continuous, or revolute over more than half a turn (a knob turned 330 degrees).
pub(crate) fn may_spin(joint: &Joint) -> bool {
    spins(joint)
        || joint.kind == JointKind::Revolute
            && joint
                .limits
                .is_some_and(|l| l.upper - l.lower > SPIN_RANGE_MIN_RAD)
}

/// How far a part (sampled at `points`) turned about the line through `pivot` along `axis` lands
/// from where it was: the mean distance of its turned samples to its samples at rest, over
/// several angles, as a share of its diagonal. Near the sampling spacing for a part round about
/// the line, a tenth or more for a part flipped about a line across it.
pub(crate) fn spin_residual(points: &[DVec3], axis: DVec3, pivot: DVec3) -> f64 {
    let axis = axis.normalize_or_zero();
    if points.is_empty() || axis == DVec3::ZERO {
        return 0.0;
    }
    let diagonal_m = Aabb::from_points(points).diagonal().max(1e-12);
    let tree = KdTree::new(points.to_vec());
    let stride = points.len().div_ceil(SPIN_SAMPLES_MAX).max(1);
    let mut sum = 0.0;
    let mut count = 0usize;
    for angle in SPIN_ANGLES_RAD {
        let turn = DQuat::from_axis_angle(axis, angle);
        for p in points.iter().step_by(stride) {
            sum += tree.nearest_distance(pivot + turn * (*p - pivot));
            count += 1;
        }
    }
    sum / count.max(1) as f64 / diagonal_m
}

/// A part is round about an axis when its roundness residual there is at most this share of its
/// diagonal (sampling alone leaves about 1 %).
pub(crate) const ROUND_RESIDUAL_MAX: f64 = 0.03;
/// The pattern search of [`round_axis`]: first steps of the axis's tilt (radians) and of the
/// line's shift (share of the diagonal), the smallest steps, and most evaluations per start.
const ROUND_SEARCH: (f64, f64, f64, usize) = (0.1, 0.05, 1e-3, 160);

/// The line about which a part (sampled at `points`) is round, if it is round about one: from
/// each of `start_axes` through the samples' centroid (which a body of revolution has on its
/// axis), a pattern search over the axis's tilt and the line's shift for the least
/// [`spin_residual`]; the best line when its residual is at most [`ROUND_RESIDUAL_MAX`].
/// Returns `(axis, a point on the line, residual)`.
pub(crate) fn round_axis(points: &[DVec3], start_axes: &[DVec3]) -> Option<(DVec3, DVec3, f64)> {
    if points.len() < 3 {
        return None;
    }
    let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
    let diagonal_m = Aabb::from_points(points).diagonal();
    let (tilt0, shift0, smallest, evaluations) = ROUND_SEARCH;
    let mut best: Option<(DVec3, DVec3, f64)> = None;
    for start in start_axes {
        let a0 = start.normalize_or_zero();
        if a0 == DVec3::ZERO {
            continue;
        }
        let e1 = a0.any_orthonormal_vector();
        let e2 = a0.cross(e1);
        let line = |x: [f64; 4]| {
            (
                (a0 + e1 * x[0] + e2 * x[1]).normalize(),
                centroid + (e1 * x[2] + e2 * x[3]) * diagonal_m,
            )
        };
        let residual = |x: [f64; 4]| {
            let (a, p) = line(x);
            spin_residual(points, a, p)
        };
        let mut x = [0.0; 4];
        let mut value = residual(x);
        let mut steps = [tilt0, tilt0, shift0, shift0];
        let mut used = 1;
        while used < evaluations && steps.iter().any(|s| *s > smallest) {
            let mut improved = false;
            for k in 0..4 {
                for sign in [1.0, -1.0] {
                    let mut y = x;
                    y[k] += sign * steps[k];
                    let v = residual(y);
                    used += 1;
                    if v < value {
                        (x, value, improved) = (y, v, true);
                        break;
                    }
                }
            }
            if !improved {
                steps.iter_mut().for_each(|s| *s *= 0.5);
            }
        }
        if best.is_none_or(|b| value < b.2) {
            let (a, p) = line(x);
            best = Some((a, p, value));
        }
    }
    best.filter(|b| b.2 <= ROUND_RESIDUAL_MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of a closed cylinder of radius 1 and height 0.5 about the z axis through the
    /// origin.
    fn cylinder() -> Vec<DVec3> {
        let mut points = Vec::new();
        for i in 0..60 {
            let a = 2.0 * PI * f64::from(i) / 60.0;
            for k in 0..6 {
                points.push(DVec3::new(a.cos(), a.sin(), 0.1 * f64::from(k)));
            }
            for r in [0.25, 0.5, 0.75] {
                points.push(DVec3::new(r * a.cos(), r * a.sin(), 0.0));
                points.push(DVec3::new(r * a.cos(), r * a.sin(), 0.5));
            }
        }
        points
    }

    #[test]
    fn a_cylinder_is_round_about_its_axis_only() {
        let points = cylinder();
        let about_axis = spin_residual(&points, DVec3::Z, DVec3::ZERO);
        let across = spin_residual(&points, DVec3::X, DVec3::new(0.0, 0.0, 0.25));
        let off_centre = spin_residual(&points, DVec3::Z, DVec3::new(0.5, 0.0, 0.0));
        assert!(about_axis < 0.02, "about its axis: {about_axis}");
        assert!(across > 5.0 * about_axis, "across: {across}");
        assert!(off_centre > 5.0 * about_axis, "off centre: {off_centre}");
    }

    #[test]
    fn the_round_axis_of_a_tilted_cylinder_is_found_from_its_box_axes() {
        let tilt = DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.07);
        let shift = DVec3::new(0.3, -0.2, 0.1);
        let points: Vec<DVec3> = cylinder().into_iter().map(|p| tilt * p + shift).collect();
        let (axis, on, residual) =
            round_axis(&points, &[DVec3::X, DVec3::Y, DVec3::Z]).expect("a cylinder is round");
        let truth = tilt * DVec3::Z;
        let angle = axis.dot(truth).abs().clamp(0.0, 1.0).acos();
        assert!(angle < 0.01, "axis off by {angle} rad");
        let off_line = (on - (tilt * DVec3::new(0.0, 0.0, 0.25) + shift))
            .reject_from_normalized(truth)
            .length();
        assert!(off_line < 0.02, "line off by {off_line}");
        assert!(residual <= ROUND_RESIDUAL_MAX);
    }

    #[test]
    fn a_tall_doors_width_across_its_hinge_is_its_width_not_its_height() {
        // 0.5 wide (x), 0.02 thick (y), 2 tall (z).
        let mut door = Vec::new();
        for i in 0..=10 {
            for k in 0..=40 {
                for y in [0.0, 0.02] {
                    door.push(DVec3::new(0.05 * f64::from(i), y, 0.05 * f64::from(k)));
                }
            }
        }
        let across_hinge = width_across_m(&door, DVec3::Z);
        let across_flap = width_across_m(&door, DVec3::X);
        assert!((across_hinge - 0.5).abs() < 0.01, "{across_hinge}");
        assert!((across_flap - 2.0).abs() < 0.01, "{across_flap}");
    }

    #[test]
    fn a_box_has_no_round_axis() {
        let mut points = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                let (u, v) = (f64::from(i) / 19.0, f64::from(j) / 19.0);
                for (x, y, z) in [
                    (u, v, 0.0),
                    (u, v, 0.3),
                    (u, 0.0, 0.3 * v),
                    (u, 1.0, 0.3 * v),
                ] {
                    points.push(DVec3::new(2.0 * x, y, z));
                }
            }
        }
        assert!(round_axis(&points, &[DVec3::X, DVec3::Y, DVec3::Z]).is_none());
    }
}
