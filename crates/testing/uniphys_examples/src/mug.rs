//! The mug: a ceramic cup (one closed shell: floor and wall) and a half-ring handle on its +x
//! side, attached rigidly; nothing moves.

use std::f64::consts::PI;

use uniphys_geometry::{DMat4, DVec3};

use crate::ExampleAsset;
use crate::assembly::Assembly;
use crate::materials::CERAMIC_GLAZE;
use crate::shapes::{lathe, quarter_turn_z_to_front, torus_segment};

const RADIUS: f64 = 0.04;
const HEIGHT: f64 = 0.095;
const WALL: f64 = 0.004;
const FLOOR: f64 = 0.006;
const SEGMENTS: u32 = 32;
/// Radius of the handle's centre line and of its round section.
const HANDLE_MAJOR: f64 = 0.03;
const HANDLE_MINOR: f64 = 0.006;
/// Gap between the handle's end caps and the cup wall.
const HANDLE_GAP: f64 = 0.0005;
const HANDLE_CENTRE_Z: f64 = 0.05;

/// Builds the mug example.
pub(crate) fn mug() -> ExampleAsset {
    let cup = lathe(
        &[
            [0.0, 0.0],
            [RADIUS, 0.0],
            [RADIUS, HEIGHT],
            [RADIUS - WALL, HEIGHT],
            [RADIUS - WALL, FLOOR],
            [0.0, FLOOR],
        ],
        SEGMENTS,
    );
    // A half ring in the xz plane, ends flat against the wall at x = RADIUS + HANDLE_GAP.
    let centre = DVec3::new(RADIUS + HANDLE_GAP, 0.0, HANDLE_CENTRE_Z);
    let handle = torus_segment(HANDLE_MAJOR, HANDLE_MINOR, -PI / 2.0, PI, 16, 12)
        .transformed(&(DMat4::from_translation(centre) * quarter_turn_z_to_front()));
    let mut a = Assembly::default();
    a.part("mug_body", CERAMIC_GLAZE, &[cup]);
    a.part("handle", CERAMIC_GLAZE, &[handle]);
    a.fixed(
        "handle",
        "mug_body",
        (centre + DVec3::new(0.0, 0.0, HANDLE_MAJOR)).to_array(),
    );
    a.finish(
        "mug",
        "A 0.08 m wide, 0.095 m tall glazed ceramic mug with a half-ring handle on its +x side; \
         a single rigid object (the handle is fixed to the body).",
    )
}
