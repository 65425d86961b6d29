//! The cabinet: an oak carcass open at the front (-y) with an upper drawer sliding out along -y
//! and a lower door hinged about its front-left vertical edge, each with a steel bar handle.

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_types::JointKind;

use crate::assembly::Assembly;
use crate::materials::{METAL_STEEL, WOOD_OAK};
use crate::shapes::{cuboid, open_top_box, quarter_turn_z_to_front};
use crate::{ExampleAsset, ExpectedJoint};

/// Outer half width (x), half depth (y) and height (z) of the carcass, metres.
const HALF_WIDTH: f64 = 0.3;
const HALF_DEPTH: f64 = 0.225;
const HEIGHT: f64 = 0.8;
/// Panel thickness of carcass and door.
const PANEL: f64 = 0.018;
/// Clearance between a moving part and the carcass.
const GAP: f64 = 0.002;
/// Bottom of the drawer; the door ends 4 mm below it.
const DRAWER_BOTTOM: f64 = 0.58;
/// Depth of the drawer along y.
const DRAWER_DEPTH: f64 = 0.42;
/// Wall thickness of the drawer tray.
const DRAWER_WALL: f64 = 0.012;
/// How far the handles stand off the fronts.
const HANDLE_STANDOFF: f64 = 0.025;

/// Builds the cabinet example.
pub(crate) fn cabinet() -> ExampleAsset {
    let front = -HALF_DEPTH;
    let inner_x = HALF_WIDTH - PANEL - GAP;
    let carcass = open_top_box(
        DVec3::new(-HALF_WIDTH, 0.0, -HALF_DEPTH),
        DVec3::new(HALF_WIDTH, HEIGHT, HALF_DEPTH),
        PANEL,
    )
    .transformed(&quarter_turn_z_to_front());

    let drawer_top = HEIGHT - PANEL - GAP;
    let drawer = open_top_box(
        DVec3::new(-inner_x, front, DRAWER_BOTTOM),
        DVec3::new(inner_x, front + DRAWER_DEPTH, drawer_top),
        DRAWER_WALL,
    );
    let drawer_mid_z = 0.5 * (DRAWER_BOTTOM + drawer_top);
    let drawer_handle = horizontal_bar_handle(DVec3::new(0.0, front, drawer_mid_z), 0.06, 0.075);

    let door_bottom = PANEL + GAP;
    let door_top = DRAWER_BOTTOM - 2.0 * GAP;
    let door = cuboid(
        DVec3::new(-inner_x, front, door_bottom),
        DVec3::new(inner_x, front + PANEL, door_top),
    );
    let door_handle_centre = DVec3::new(inner_x - 0.05, front, 0.30);
    let door_handle = vertical_bar_handle(door_handle_centre, 0.05, 0.065);

    let mut a = Assembly::default();
    a.part("cabinet_body", WOOD_OAK, &[carcass]);
    a.part("drawer", WOOD_OAK, &[drawer]);
    a.part("drawer_handle", METAL_STEEL, &drawer_handle);
    a.part("door", WOOD_OAK, &[door]);
    a.part("door_handle", METAL_STEEL, &door_handle);
    a.joint(ExpectedJoint {
        child: "drawer",
        parent: "cabinet_body",
        kind: JointKind::Prismatic,
        axis: [0.0, -1.0, 0.0],
        pivot: [0.0, front, drawer_mid_z],
        limits: (0.0, 0.8 * DRAWER_DEPTH),
    });
    a.fixed("drawer_handle", "drawer", [0.06, front, drawer_mid_z]);
    a.joint(ExpectedJoint {
        child: "door",
        parent: "cabinet_body",
        kind: JointKind::Revolute,
        axis: [0.0, 0.0, -1.0],
        pivot: [-inner_x, front, door_bottom],
        limits: (0.0, 1.6),
    });
    a.fixed(
        "door_handle",
        "door",
        (door_handle_centre + DVec3::new(0.0, 0.0, 0.05)).to_array(),
    );
    a.finish(
        "cabinet",
        "A 0.6 x 0.45 x 0.8 m oak cabinet open at the front (-y): the upper drawer slides out \
         along -y, the lower door swings outwards about its front-left vertical edge; both have \
         fixed steel bar handles.",
    )
}

/// A bar handle along x centred in front of `centre` (a point on a front face at y = centre.y):
/// two 10 mm square posts at x = +/-`post_offset` and a grip of half length `half_length`.
fn horizontal_bar_handle(centre: DVec3, post_offset: f64, half_length: f64) -> Vec<TriMesh> {
    bar_handle(centre, DVec3::X, post_offset, half_length)
}

/// A bar handle along z, as [`horizontal_bar_handle`].
fn vertical_bar_handle(centre: DVec3, post_offset: f64, half_length: f64) -> Vec<TriMesh> {
    bar_handle(centre, DVec3::Z, post_offset, half_length)
}

/// Posts (10 mm square) from the front face out to the grip (12 mm deep, 16 mm wide, 24 mm
/// longer than the post spacing on each side). Posts and grip touch without sharing edges.
fn bar_handle(centre: DVec3, along: DVec3, post_offset: f64, half_length: f64) -> Vec<TriMesh> {
    let across = if along == DVec3::X {
        DVec3::Z
    } else {
        DVec3::X
    };
    let out = DVec3::NEG_Y;
    let post_face = centre + out * HANDLE_STANDOFF;
    let mut shells: Vec<TriMesh> = [-post_offset, post_offset]
        .iter()
        .map(|&offset| {
            let c = centre + along * offset;
            let half = (along + across) * 0.005;
            corner_box(c - half, post_face + along * offset + half)
        })
        .collect();
    let half = along * half_length + across * 0.008;
    shells.push(corner_box(post_face - half, post_face + out * 0.012 + half));
    shells
}

/// The box spanned by two opposite corners given in any order.
fn corner_box(a: DVec3, b: DVec3) -> TriMesh {
    cuboid(a.min(b), a.max(b))
}
