//! The laptop: a plastic base slab and an aluminium lid hinged about the back top edge of the
//! base (an x-parallel axis), posed open at 100 degrees, with a glass screen fixed to the lid.

use uniphys_geometry::DVec3;
use uniphys_types::JointKind;

use crate::assembly::Assembly;
use crate::materials::{GLASS_BLACK, METAL_ALUMINIUM, PLASTIC_ABS};
use crate::shapes::{cuboid, rotation_about};
use crate::{ExampleAsset, ExpectedJoint};

const HALF_WIDTH: f64 = 0.16;
const HALF_DEPTH: f64 = 0.11;
const BASE_THICKNESS: f64 = 0.015;
const LID_THICKNESS: f64 = 0.006;
/// Clearance between the closed lid and the base, and at the hinge.
const LID_GAP: f64 = 0.0015;
const SCREEN_THICKNESS: f64 = 0.0005;
/// Opening angle of the posed lid (angle between lid and base), radians.
pub(crate) const OPEN_ANGLE: f64 = 100.0 * std::f64::consts::PI / 180.0;
/// How much further than the pose the lid can open, radians.
const EXTRA_OPENING: f64 = 0.5;

/// Builds the laptop example.
pub(crate) fn laptop() -> ExampleAsset {
    let base = cuboid(
        DVec3::new(-HALF_WIDTH, -HALF_DEPTH, 0.0),
        DVec3::new(HALF_WIDTH, HALF_DEPTH, BASE_THICKNESS),
    );
    let lid_bottom = BASE_THICKNESS + LID_GAP;
    let closed_lid = cuboid(
        DVec3::new(-HALF_WIDTH, -HALF_DEPTH, lid_bottom),
        DVec3::new(HALF_WIDTH, HALF_DEPTH, lid_bottom + LID_THICKNESS),
    );
    let closed_screen = cuboid(
        DVec3::new(-0.145, -0.100, lid_bottom - SCREEN_THICKNESS),
        DVec3::new(0.145, 0.095, lid_bottom),
    );
    let pivot = DVec3::new(0.0, HALF_DEPTH, BASE_THICKNESS);
    let axis = DVec3::NEG_X;
    let pose = rotation_about(pivot, axis, OPEN_ANGLE);
    let screen_contact = pose.transform_point3(DVec3::new(0.0, -0.0025, lid_bottom));

    let mut a = Assembly::default();
    a.part("base", PLASTIC_ABS, &[base]);
    a.part("lid", METAL_ALUMINIUM, &[closed_lid.transformed(&pose)]);
    a.part("screen", GLASS_BLACK, &[closed_screen.transformed(&pose)]);
    a.joint(ExpectedJoint {
        child: "lid",
        parent: "base",
        kind: JointKind::Revolute,
        axis: axis.to_array(),
        pivot: pivot.to_array(),
        limits: (-OPEN_ANGLE, EXTRA_OPENING),
    });
    a.fixed("screen", "lid", screen_contact.to_array());
    a.finish(
        "laptop",
        "A 0.32 x 0.22 m laptop: the lid is hinged about the back top edge of the base (axis -x, \
         positive opens) and posed open at 100 degrees, so it closes at -100 degrees; the screen \
         is fixed to the lid.",
    )
}
