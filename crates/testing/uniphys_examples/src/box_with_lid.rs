//! The box with a lid: an open-topped pine box and a flat lid resting closed 1.5 mm above its
//! walls, hinged about the back top edge so that it opens upwards.

use uniphys_geometry::DVec3;
use uniphys_types::JointKind;

use crate::assembly::Assembly;
use crate::materials::WOOD_PINE;
use crate::shapes::{cuboid, open_top_box};
use crate::{ExampleAsset, ExpectedJoint};

const HALF_WIDTH: f64 = 0.15;
const HALF_DEPTH: f64 = 0.10;
const HEIGHT: f64 = 0.15;
const WALL: f64 = 0.008;
const LID_THICKNESS: f64 = 0.008;
const LID_GAP: f64 = 0.0015;

/// Builds the box-with-lid example.
pub(crate) fn box_with_lid() -> ExampleAsset {
    let body = open_top_box(
        DVec3::new(-HALF_WIDTH, -HALF_DEPTH, 0.0),
        DVec3::new(HALF_WIDTH, HALF_DEPTH, HEIGHT),
        WALL,
    );
    let lid = cuboid(
        DVec3::new(-HALF_WIDTH, -HALF_DEPTH, HEIGHT + LID_GAP),
        DVec3::new(HALF_WIDTH, HALF_DEPTH, HEIGHT + LID_GAP + LID_THICKNESS),
    );
    let mut a = Assembly::default();
    a.part("box_body", WOOD_PINE, &[body]);
    a.part("lid", WOOD_PINE, &[lid]);
    a.joint(ExpectedJoint {
        child: "lid",
        parent: "box_body",
        kind: JointKind::Revolute,
        axis: [-1.0, 0.0, 0.0],
        pivot: [0.0, HALF_DEPTH, HEIGHT],
        limits: (0.0, 1.9),
    });
    a.finish(
        "box_with_lid",
        "A 0.3 x 0.2 x 0.15 m open pine box with a closed flat lid hinged about the back top \
         edge (axis -x, positive opens upwards).",
    )
}
