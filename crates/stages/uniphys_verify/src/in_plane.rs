//! A flat panel turned in its own plane, like a clock hand, measured at rest.
//!
//! A sweep alone passes a door spun about its hinge corner in the plane of the cabinet's front:
//! it slides flush over the front and passes through nothing. Real panels that turn about their
//! own normal are of two kinds:
//! - round about the axis (a knob's disc, a cap, a lens ring): turned, the part lands on itself;
//! - held across both faces (a folding knife's blade between the handle's scales): the parent
//!   forms a slot the panel turns in, as a drawer's carcass does for the drawer.
//!
//! A panel that is neither has nothing that makes it turn that way: its hinge is along an edge.
//! A held panel turns on a pin through the region its parent holds: that region gives pivot
//! candidates ([`held_pivots`]).

use uniphys_geometry::{DVec3, box_axes};

use crate::fit::spin_residual;
use crate::handle::{axis_across_panel, is_panel};
use crate::held::{mean, rest_contact_m};
use crate::part_box::{Boxed, PartBox};
use crate::rounded_ends::rounded_end_pivots;
use crate::scene::Scene;
use crate::sweep_params::SweepParams;

/// Most moving samples probed for the parts over and under the panel.
const PROBE_SAMPLES_MAX: usize = 1000;
/// A held region of fewer samples gives no pivots.
const HELD_SAMPLES_MIN: usize = 8;

/// How a panel turned about an axis across its plane is held: its roundness about the axis and
/// how much of it lies between still surfaces on both faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InPlaneTurn {
    /// The roundness residual about the joint's line (see `fit::spin_residual`), a share of
    /// the moving parts' diagonal.
    pub residual: f64,
    /// Of the moving samples with a still surface close over or under them along the axis, the
    /// share with one on both sides (1: the panel lies in a slot; 0: on one face of its
    /// parent).
    pub sandwiched_share: f64,
}

/// The in-plane turn of the moving group (sampled at `moving`) about the line through `pivot`
/// along `axis`, or `None` when the group is no panel (its thinnest box extent at least
/// [`crate::PANEL_SLAB_RATIO`] of its middle one) or the axis runs along its plane. A still
/// part (`still`) is close along the axis when it lies within the panel's thickness plus
/// `touch_m` of a sample, the reach of a slot's far wall from a sample on the near face.
pub(crate) fn in_plane_turn(
    scene: &Scene,
    moving: &Boxed<'_>,
    still: &[usize],
    axis: DVec3,
    pivot: DVec3,
    touch_m: f64,
) -> Option<InPlaneTurn> {
    let axis = axis.normalize_or_zero();
    let part = panel_turned_across(moving, axis)?;
    let moving = moving.points;
    let (one_side, both_sides) = probe_faces(scene, moving, still, axis, part, touch_m);
    let probed = one_side + both_sides.len();
    Some(InPlaneTurn {
        residual: spin_residual(moving, axis, pivot),
        sandwiched_share: if probed == 0 {
            0.0
        } else {
            both_sides.len() as f64 / probed as f64
        },
    })
}

/// Pivots of lines along `axis` where a panel held across both faces by its parent turns (a
/// folding knife's blade on the pin through its handle's scales): the mean of the moving
/// group's samples (parts `moving`) with a still part close over and under them along the axis
/// (as the in-plane rule probes, within the panel's thickness plus the rest-contact distance of
/// `params`), and the centres of that held region's rounded ends ([`rounded_end_pivots`]).
/// Empty when the moving group is no panel, the axis runs along its plane or nothing holds it
/// on both faces. Object frame, metres.
#[must_use]
pub fn held_pivots(
    scene: &Scene,
    moving: &[usize],
    axis: DVec3,
    params: &SweepParams,
) -> Vec<DVec3> {
    let axis = axis.normalize_or_zero();
    let points = scene.points_of(moving);
    let boxed = Boxed::new(&points);
    let Some(part) = panel_turned_across(&boxed, axis) else {
        return Vec::new();
    };
    let still = scene.still_parts(moving);
    let touch_m = rest_contact_m(params, part.diagonal, scene.diagonal_m);
    let (_, held) = probe_faces(scene, &points, &still, axis, part, touch_m);
    if held.len() < HELD_SAMPLES_MIN {
        return Vec::new();
    }
    let mut out = vec![mean(&held)];
    out.extend(rounded_end_pivots(&held, axis, box_axes(&held)));
    out
}

/// The box of the moving group (sampled at `points`) when it is a panel and unit `axis` (zero
/// for none) crosses its plane; `None` otherwise.
fn panel_turned_across<'b>(points: &'b Boxed<'_>, axis: DVec3) -> Option<&'b PartBox> {
    if points.points.len() < 3 || axis == DVec3::ZERO {
        return None;
    }
    let part = points.part_box();
    (is_panel(part) && axis_across_panel(part, axis)).then_some(part)
}

/// Probes up to [`PROBE_SAMPLES_MAX`] of the panel's samples along `axis` both ways for a
/// still part within the panel's thickness plus `touch_m`: how many have one on one side only,
/// and the samples with one on both sides.
fn probe_faces(
    scene: &Scene,
    moving: &[DVec3],
    still: &[usize],
    axis: DVec3,
    part: &PartBox,
    touch_m: f64,
) -> (usize, Vec<DVec3>) {
    let reach_m = part.sorted_extents()[0] + touch_m;
    let close = |from: DVec3, direction: DVec3| {
        still.iter().any(|&s| {
            scene
                .surfaces
                .crossing(s, from, from + direction * reach_m)
                .is_some()
        })
    };
    let (mut one_side, mut both_sides) = (0usize, Vec::new());
    let stride = moving.len().div_ceil(PROBE_SAMPLES_MAX).max(1);
    for p in moving.iter().step_by(stride) {
        match (close(*p, axis), close(*p, -axis)) {
            (true, true) => both_sides.push(*p),
            (true, false) | (false, true) => one_side += 1,
            (false, false) => {}
        }
    }
    (one_side, both_sides)
}
