//! Spin axes: a part that maps onto itself when turned about an axis (a knob, a wheel, a round
//! cap or lid) can turn about it without sweeping any new space, so it turns continuously.
//!
//! Candidate axes are the part's box axes, its principal axes and the direction toward its
//! parent; the best is refined by small tilts, since a box fitted to a knob with a grip or a
//! wheel with a tread can be a few degrees off its true axis. The tilt decides whether the part
//! is round; the axis stays the candidate when the tilt is small.

use uniphys_geometry::{DQuat, DVec3, extent_along, principal_axes};
use uniphys_verify::{
    ON_SURFACE_FRACTION, RoundAxis, Scene, across, centre_about, kept_about_line,
};

use crate::motion_search::PartBox;

/// Share of the turned samples that must be back on the part at every turn.
const KEPT_FRACTION_MIN: f64 = 0.85;
/// A refined axis within this angle of its candidate (cosine of 15 degrees) is the candidate.
const SNAP_COS: f64 = 0.965_925_8;
/// Tilts tried around the best candidate axis, radians (3 and 1 degrees).
const TILTS_RAD: [f64; 2] = [0.052_359_88, 0.017_453_29];

/// The smallest share of the outer `points` that land back on the part's surface over the
/// test turns about the line along `axis` through the middle of the points' box
/// ([`kept_about_line`]).
fn kept_fraction(scene: &Scene, part: usize, points: &[DVec3], axis: DVec3, tolerance: f64) -> f64 {
    kept_about_line(
        scene,
        part,
        points,
        axis,
        centre_about(points, axis),
        tolerance,
    )
}

/// How round `part` (sampled at `points`, its box `part_box`) is about the line along `axis`
/// through `through`: the smallest share of its outer samples back on it over the test turns
/// ([`kept_fraction`]), the best over the small tilts [`spin_axis`] tries (a line found from
/// contact leans a few degrees). A cap with a spout keeps most; a lever, little.
pub(crate) fn roundness_about(
    scene: &Scene,
    part: usize,
    points: &[DVec3],
    part_box: &PartBox,
    axis: DVec3,
    through: DVec3,
) -> f64 {
    let tolerance = ON_SURFACE_FRACTION * part_box.diagonal;
    let (u, v) = across(axis);
    std::iter::once(axis)
        .chain(
            TILTS_RAD
                .iter()
                .flat_map(|&tilt| [u, -u, v, -v].map(|d| DQuat::from_axis_angle(d, tilt) * axis)),
        )
        .map(|a| kept_about_line(scene, part, points, a, through, tolerance))
        .fold(0.0, f64::max)
}

/// The axis `part` (sampled at `points`, its box `part_box`) is round about, if any; when several
/// are (a ball), the one most aligned with `prefer` (toward the parent).
pub(crate) fn spin_axis(
    scene: &Scene,
    part: usize,
    points: &[DVec3],
    part_box: &PartBox,
    prefer: DVec3,
) -> Option<RoundAxis> {
    if points.len() < 16 {
        return None;
    }
    let tolerance = ON_SURFACE_FRACTION * part_box.diagonal;
    let mut candidates: Vec<DVec3> = part_box.axes.to_vec();
    candidates.extend(principal_axes(points));
    if prefer.length_squared() > 0.5 {
        candidates.push(prefer.normalize());
    }
    // Rank: the share kept, plus a small preference for the axis toward the parent (a ball).
    let rank = |axis: DVec3, kept: f64| kept + 0.05 * axis.dot(prefer).abs();
    let mut scored: Vec<(DVec3, f64)> = candidates
        .iter()
        .map(|&a| (a, kept_fraction(scene, part, points, a, tolerance)))
        .collect();
    scored.sort_by(|a, b| rank(b.0, b.1).total_cmp(&rank(a.0, a.1)));
    let (mut axis, mut kept) = *scored.first()?;
    let unrefined = axis;
    for tilt in TILTS_RAD {
        let (u, v) = across(axis);
        for d in [u, -u, v, -v] {
            let tilted = DQuat::from_axis_angle(d, tilt) * axis;
            let k = kept_fraction(scene, part, points, tilted, tolerance);
            if k > kept {
                (axis, kept) = (tilted, k);
            }
        }
    }
    if kept < KEPT_FRACTION_MIN {
        return None;
    }
    // Made things are round about their own box or principal axes: a tilt only shows that the
    // part is nearly round, so the axis stays the candidate it came from when that is close.
    if axis.dot(unrefined).abs() >= SNAP_COS {
        axis = unrefined;
    }
    let (u, v) = across(axis);
    let extent = |d: DVec3| extent_along(points, d);
    let width_m = extent(u).max(extent(v));
    Some(RoundAxis {
        axis,
        centre: centre_about(points, axis),
        kept_fraction: kept,
        width_m,
        length_over_width: extent(axis) / width_m.max(1e-12),
    })
}
