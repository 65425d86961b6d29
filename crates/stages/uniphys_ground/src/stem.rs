//! Stems: a part held to its parent by one small flat patch (a faucet's lever on its cartridge,
//! a tap's cross handle, a spout on its collar, a knife's blade on its pin, a cap on a neck).
//! A part held so can turn about the patch's normal through the patch's middle, the line a
//! stem or pin runs along, without its hold moving: the patch turns in its own plane. A hinge
//! along an edge of its box would tear the patch off, so a part with a stem twists on it when
//! the sweep lets it turn a quarter turn, over any line of its box (`crate::motion_search`).

use std::f64::consts::FRAC_PI_2;

use uniphys_geometry::{DVec3, extent_along, principal_axes};
use uniphys_types::{Joint, JointKind, JointLimits};
use uniphys_verify::Scene;

use crate::hinge_range::{folding_way, free_turns};
use crate::hypotheses::mean;
use crate::motion_search::{Mover, PartBox};
use crate::spin::roundness_about;

/// A patch whose longest extent is at most this share of the part's box diagonal is small: the
/// part overhangs it on every side (a lever, a handle). A door's or a lid's contact runs along
/// a whole edge or rim, well over half its diagonal.
const STEM_EXTENT_FRACTION: f64 = 0.45;
/// A patch whose thickness (its extent along its normal) is at most this share of its middle
/// extent is flat: it has a normal. A blob of contact (an axle in a hole) has none.
const FLAT_RATIO: f64 = 0.3;
/// Fewest contact samples to judge a patch's shape.
const PATCH_SAMPLES_MIN: usize = 12;
/// A lever that nothing the sweep sees stops turns this far each way from rest (a quarter turn,
/// as a single-lever tap's: its stops are inside the cartridge, out of sight).
const LEVER_TURN_RAD: f64 = FRAC_PI_2;

/// A part twisting on its stem that nothing stops spins freely (a cap, a dial) when at least this
/// share of its outline maps onto itself turned about the stem's line (a cap with a spout: 0.71
/// to 0.73 in any pose); a lever or a cross handle, far from round about it (0), turns a quarter
/// turn each way instead.
const ROUND_STEM_KEPT_MIN: f64 = 0.5;

/// The line a part held by a stem turns about: the unit normal of its contact patch and the
/// patch's middle, object frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stem {
    pub normal: DVec3,
    pub centre: DVec3,
}

/// The stem of a part whose samples within touching distance of its parent are `touching`, if
/// that contact is one small flat patch.
pub(crate) fn stem(touching: &[DVec3], part: &PartBox) -> Option<Stem> {
    if touching.len() < PATCH_SAMPLES_MIN {
        return None;
    }
    let axes = principal_axes(touching);
    let [longest, middle, thickness] = axes.map(|a| extent_along(touching, a));
    let small = longest <= STEM_EXTENT_FRACTION * part.diagonal;
    let flat = thickness <= FLAT_RATIO * middle;
    (small && flat).then(|| Stem {
        normal: axes[2],
        centre: mean(touching),
    })
}

/// The joint of a part twisting on its stem (the chosen twist hypothesis `twist`) with its range
/// from sweeps each way: a part nothing stops spins when it is mostly round about the stem (a
/// cap), and otherwise turns a quarter turn each way (a lever: its stops are out of sight); a
/// part something stops turns until it collides each way, its axis turned so that the wider
/// side is positive. Stops either way that add up to a full turn are one obstacle met from both
/// sides (a folding blade meeting its handle one way round and the other): it turns one way
/// only, the one that folds it into the object, or the shorter when neither does more
/// ([`folding_way`]).
pub(crate) fn twist_joint(
    scene: &Scene,
    mover: &Mover<'_>,
    twist: &Joint,
) -> (Joint, &'static str) {
    let Some(turns) = free_turns(scene, mover, twist) else {
        return (twist.clone(), "range kept from the search");
    };
    let axis = DVec3::from_array(twist.axis_in_object);
    let with = |axis: DVec3, lower: f64, upper: f64| {
        let mut joint = twist.clone();
        joint.axis_in_object = axis.to_array();
        joint.limits = Some(JointLimits { lower, upper });
        joint
    };
    if turns.unbounded() {
        let points = scene.points_of(&[mover.child]);
        let through = DVec3::from_array(twist.pivot_in_object_m);
        let round = roundness_about(
            scene,
            mover.child,
            &points,
            &mover.boxes[mover.child],
            axis,
            through,
        );
        if round >= ROUND_STEM_KEPT_MIN {
            let mut joint = twist.clone();
            joint.kind = JointKind::Continuous;
            joint.limits = None;
            return (
                joint,
                "nothing seen stops it and it is mostly round about its stem, a cap or a dial: it spins",
            );
        }
        return (
            with(axis, -LEVER_TURN_RAD, LEVER_TURN_RAD),
            "nothing seen stops it: a quarter turn each way",
        );
    }
    if turns.one_obstacle() {
        let (axis, upper) = folding_way(scene, mover, twist, &turns);
        return (
            with(axis, 0.0, upper),
            "stopped both ways by one obstacle: turns the way that folds it into the object",
        );
    }
    let (axis, wide, narrow) = if turns.forward >= turns.backward {
        (axis, turns.forward, turns.backward)
    } else {
        (-axis, turns.backward, turns.forward)
    };
    (
        with(axis, -narrow, wide),
        "turns both ways until it collides",
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_points::box_grid;

    /// Points filling the box `[lo, hi]` on a grid.
    fn grid(lo: DVec3, hi: DVec3) -> Vec<DVec3> {
        box_grid(lo, hi, 5)
    }

    #[test]
    fn a_lever_on_a_small_pad_has_a_stem_along_the_pads_normal() {
        // A lever 0.4 long over a pad 0.06 across, resting on it from above.
        let lever = PartBox::of(&grid(
            DVec3::new(-0.05, -0.03, 0.0),
            DVec3::new(0.35, 0.03, 0.04),
        ));
        let pad = grid(DVec3::new(-0.03, -0.03, 0.0), DVec3::new(0.03, 0.03, 0.002));
        let stem = stem(&pad, &lever).expect("a small flat pad is a stem");
        assert!(stem.normal.dot(DVec3::Z).abs() > 0.99, "{:?}", stem.normal);
        assert!(stem.centre.truncate().length() < 1e-9);
    }

    #[test]
    fn a_door_touching_along_its_edge_or_a_blob_of_contact_has_no_stem() {
        let door = PartBox::of(&grid(DVec3::ZERO, DVec3::new(0.02, 0.6, 1.0)));
        let edge = grid(DVec3::ZERO, DVec3::new(0.02, 0.02, 1.0));
        assert!(stem(&edge, &door).is_none());
        // A contact as thick as it is wide (an axle in its hole) has no normal.
        let wheel = PartBox::of(&grid(DVec3::ZERO, DVec3::new(0.3, 0.3, 0.1)));
        let blob = grid(DVec3::splat(0.1), DVec3::splat(0.15));
        assert!(stem(&blob, &wheel).is_none());
    }
}
