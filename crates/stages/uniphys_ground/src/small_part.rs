//! Small parts (a button, a key, a knob, a dial): they move along the normal of the face they
//! sit on. A flat one, or a round one that a hand cannot turn (smooth all round and squat, on a
//! face of its parent), is pushed a short way into its parent; one that is not round but stands
//! out of the face by 40 % of its width or more is gripped and turned. A push travels half the
//! part's depth, or a tenth of its width when it is drawn without thickness.

use uniphys_geometry::{DVec3, extent_along, principal_axes};
use uniphys_types::JointKind;
use uniphys_verify::{RoundAxis, Scene, across, push_travel_m};

use crate::motion_search::{Motion, Mover, PartBox, TOUCH_FRACTION, joint, touching};

/// A small part that is not round but stands out of its parent's face by this fraction of its
/// width or more is gripped and turned (a knob with a grip bar); flatter ones are pushed.
const KNOB_RATIO: f64 = 0.4;
/// A small part whose own axis is within this angle (cosine of 20 degrees) of the normal of the
/// face it touches its parent on moves along that normal.
const FACE_NORMAL_COS: f64 = 0.939_692_6;
/// The motion of a small part (`size_share`: its box diagonal over its parent's); `spin` is its
/// round axis if it has one (a round button: round parts that turn spin before this is asked),
/// `inward` the direction toward its parent.
pub(crate) fn small_part_motion(
    scene: &Scene,
    mover: &Mover<'_>,
    child_points: &[DVec3],
    part: &PartBox,
    spin: Option<RoundAxis>,
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
    let travel = push_travel_m(depth, width);
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
