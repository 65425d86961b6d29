//! Small parts (a button, a key, a knob, a dial): they move along the normal of the face they
//! sit on. A flat one, or a round one that a hand cannot turn (smooth all round and squat, on a
//! face of its parent), is pushed a short way into its parent; one that is not round but stands
//! out of the face by 40 % of its width or more is gripped and turned. A push travels half the
//! part's depth, or a tenth of its width when it is drawn without thickness.

use uniphys_geometry::{DVec3, principal_axes, projection_range};
use uniphys_types::JointKind;
use uniphys_verify::Scene;

use crate::hypotheses::extent_along;
use crate::motion_search::{Motion, Mover, PartBox, TOUCH_FRACTION, joint, touching};
use crate::spin::{Spin, across};

/// A small part that is not round but stands out of its parent's face by this fraction of its
/// width or more is gripped and turned (a knob with a grip bar); flatter ones are pushed.
const KNOB_RATIO: f64 = 0.4;
/// A push travels this share of the part's depth along its axis.
const PUSH_TRAVEL_FRACTION: f64 = 0.5;
/// A part whose depth along its push is under this share of its width is drawn as a single
/// surface (no thickness) ...
const FLAT_DEPTH_FRACTION: f64 = 0.01;
/// ... and is pushed this share of its width (a few millimetres for a finger-sized button).
const FLAT_STROKE_FRACTION: f64 = 0.1;
/// A small part whose own axis is within this angle (cosine of 20 degrees) of the normal of the
/// face it touches its parent on moves along that normal.
const FACE_NORMAL_COS: f64 = 0.939_692_6;
/// A round small part is turned when a hand can hold it: it stands this tall along its axis, as
/// a share of its width, to be pinched by its sides (a stub knob) ...
const PINCH_RATIO: f64 = 0.6;
/// ... or its outline is round only up to a grip (a ridge, a pointer, a knurl): under this share
/// of its outline maps onto itself when turned. Smooth all round and squat, it gives the fingers
/// nothing to turn it by: a button.
const SMOOTH_KEPT_FRACTION: f64 = 0.95;
/// Directions around a round part's axis in which its parent's face is looked for ...
const FACE_DIRECTIONS: usize = 8;
/// ... and in how many of them the face must lie beside the part for it to sit on that face (a
/// button on a panel, possibly near its edge), rather than on the end of a neck it caps or an
/// axle it rolls on (the parent beside it in a few directions at most).
const FACE_DIRECTIONS_MIN: usize = 6;
/// Distances from the axis, in the part's widths, at which the face is looked for: from just
/// past its rim to half a width beyond it.
const FACE_REACH_WIDTHS: [f64; 3] = [0.7, 0.85, 1.0];
/// The face is there when the parent's surface lies within this share of the part's width of a
/// probe (probes are this far apart along the axis, over the part's length and as far past it).
const FACE_TOLERANCE_WIDTHS: f64 = 0.1;

/// The motion of a small part (`size_share`: its box diagonal over its parent's); `spin` is its
/// round axis if it has one (a round button: round parts that turn spin before this is asked),
/// `inward` the direction toward its parent.
pub(crate) fn small_part_motion(
    scene: &Scene,
    mover: &Mover<'_>,
    child_points: &[DVec3],
    part: &PartBox,
    spin: Option<Spin>,
    inward: DVec3,
    size_share: f64,
) -> Motion {
    // The box axis facing the parent; a round button pushes along its own axis.
    let k = (0..3)
        .max_by(|&a, &b| {
            let facing = |k: usize| part.axes[k].dot(inward).abs();
            facing(a).total_cmp(&facing(b))
        })
        .unwrap_or(0);
    // It moves along the normal of the face it sits on: the plane through the samples where
    // it touches its parent (a slanted control panel) when that is close to its own axis.
    let own = spin.map_or(part.axes[k], |s| s.axis);
    let touch_m = TOUCH_FRACTION * scene.diagonal_m;
    let touching = touching(scene, mover.parent, child_points, touch_m);
    let face = (touching.len() >= 12).then(|| principal_axes(&touching)[2]);
    let normal = face
        .filter(|f| f.dot(own).abs() >= FACE_NORMAL_COS)
        .unwrap_or(own);
    let normal = if normal.dot(inward) < 0.0 {
        -normal
    } else {
        normal
    };
    let depth = extent_along(child_points, normal);
    let width = {
        let (u, v) = across(normal);
        extent_along(child_points, u).max(extent_along(child_points, v))
    };
    let share = 100.0 * size_share;
    if spin.is_none() && depth >= KNOB_RATIO * width {
        return Motion {
            joint: Some(joint(
                mover,
                JointKind::Continuous,
                normal,
                part.centre,
                None,
                "a small part standing out of its parent's face: turned".to_owned(),
            )),
            summary: format!(
                "small ({share:.0} % of its parent's size), standing out {:.0} % of its width: a knob, continuous",
                100.0 * depth / width.max(1e-12)
            ),
        };
    }
    let travel = push_travel(depth, width);
    Motion {
        joint: Some(joint(
            mover,
            JointKind::Prismatic,
            normal,
            part.centre,
            Some(travel.max(1e-6)),
            "a small part on its parent's face: pushed in".to_owned(),
        )),
        summary: format!(
            "small ({share:.0} % of its parent's size) and {}: pushed {travel:.4} into its parent",
            if spin.is_some() {
                "round but smooth and squat on its face, nothing to turn it by"
            } else {
                "flat or square"
            }
        ),
    }
}

/// Whether a small part round about `spin` is a button rather than a knob, a cap or a wheel: a
/// hand cannot turn it (it is smooth all round and squat) and it sits on a face of its `parent`.
pub(crate) fn pushed_not_turned(
    scene: &Scene,
    parent: usize,
    child_points: &[DVec3],
    spin: &Spin,
) -> bool {
    let graspable =
        spin.length_over_width >= PINCH_RATIO || spin.kept_fraction < SMOOTH_KEPT_FRACTION;
    !graspable && face_directions(scene, parent, child_points, spin) >= FACE_DIRECTIONS_MIN
}

/// In how many of [`FACE_DIRECTIONS`] directions around a round part's axis its parent's surface
/// lies beside it, at its own height along the axis (or within the tolerance past either end).
fn face_directions(scene: &Scene, parent: usize, child_points: &[DVec3], spin: &Spin) -> usize {
    let (lo, hi) = projection_range(child_points, spin.axis);
    let (u, v) = across(spin.axis);
    let width = spin.width_m;
    let tolerance = FACE_TOLERANCE_WIDTHS * width;
    if tolerance <= 0.0 {
        return 0;
    }
    let levels = ((hi - lo) / tolerance).ceil() as usize + 2;
    let on_axis = spin.centre - spin.axis * spin.centre.dot(spin.axis);
    (0..FACE_DIRECTIONS)
        .filter(|&k| {
            let angle = k as f64 * std::f64::consts::TAU / FACE_DIRECTIONS as f64;
            let out = u * angle.cos() + v * angle.sin();
            FACE_REACH_WIDTHS.iter().any(|reach| {
                (0..=levels).any(|level| {
                    let height = lo - tolerance + level as f64 * tolerance;
                    let probe = on_axis + spin.axis * height + out * (reach * width);
                    scene.distance_to_surface_m(parent, probe) <= tolerance
                })
            })
        })
        .count()
}

/// How far a small part of `depth` along its push and `width` across it is pushed: half its
/// depth, or a tenth of its width when it is drawn as a single surface and has no depth to read
/// its stroke from.
fn push_travel(depth: f64, width: f64) -> f64 {
    if depth < FLAT_DEPTH_FRACTION * width {
        FLAT_STROKE_FRACTION * width
    } else {
        PUSH_TRAVEL_FRACTION * depth
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_button_is_pushed_half_its_depth_and_one_without_thickness_a_tenth_of_its_width() {
        assert!((push_travel(0.008, 0.05) - 0.004).abs() < 1e-12);
        assert!((push_travel(0.0, 0.05) - 0.005).abs() < 1e-12);
    }
}
