//! Spin axes: a part that maps onto itself when turned about an axis (a knob, a wheel, a round
//! cap or lid) can turn about it without sweeping any new space, so it turns continuously.
//!
//! Candidate axes are the part's box axes, its principal axes and the direction toward its
//! parent; the best is refined by small tilts, since a box fitted to a knob with a grip or a
//! wheel with a tread can be a few degrees off its true axis. The tilt decides whether the part
//! is round; the axis stays the candidate when the tilt is small.

use uniphys_geometry::{DQuat, DVec3, principal_axes, projection_range};
use uniphys_verify::Scene;

use crate::hypotheses::extent_along;
use crate::motion_search::PartBox;

/// Turns at which the part is compared with itself, radians (30, 75 and 130 degrees): no
/// rectangle or square maps onto itself at any of them, a round part does at all.
const TURNS_RAD: [f64; 3] = [
    std::f64::consts::FRAC_PI_6,
    5.0 * std::f64::consts::PI / 12.0,
    13.0 * std::f64::consts::PI / 18.0,
];
/// A turned sample is back on the part when it lies within this fraction of the part's
/// diagonal of the part's own surface.
const ON_SURFACE_FRACTION: f64 = 0.02;
/// Samples at least this share of the farthest sample's distance from the axis are judged.
const OUTER_RADIUS_FRACTION: f64 = 0.5;
/// Share of the turned samples that must be back on the part at every turn.
const KEPT_FRACTION_MIN: f64 = 0.85;
/// A refined axis within this angle of its candidate (cosine of 15 degrees) is the candidate.
const SNAP_COS: f64 = 0.965_925_8;
/// Tilts tried around the best candidate axis, radians (3 and 1 degrees).
const TILTS_RAD: [f64; 2] = [0.052_359_88, 0.017_453_29];

/// An axis the part is round about.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Spin {
    /// Unit axis, object frame.
    pub axis: DVec3,
    /// A point on it: the middle of the part's extent across and along the axis, object frame.
    pub centre: DVec3,
    /// The smallest share of turned samples back on the part over the test turns.
    pub kept_fraction: f64,
    /// The part's largest extent across the axis, metres.
    pub width_m: f64,
    /// The part's extent along the axis over [`Self::width_m`]: a squat part (a button, a dial)
    /// is low, a stub (a knob to pinch, a bottle) high.
    pub length_over_width: f64,
}

/// Two unit vectors completing `axis` to an orthonormal frame.
pub(crate) fn across(axis: DVec3) -> (DVec3, DVec3) {
    let u = axis.any_orthonormal_vector();
    (u, axis.cross(u))
}

/// The centre of the points' box in the frame of `axis`.
fn centre_about(points: &[DVec3], axis: DVec3) -> DVec3 {
    let (u, v) = across(axis);
    [axis, u, v]
        .iter()
        .map(|d| {
            let (lo, hi) = projection_range(points, *d);
            *d * (0.5 * (lo + hi))
        })
        .sum()
}

/// The smallest share of the outer `points` (at least [`OUTER_RADIUS_FRACTION`] of the farthest
/// one's distance from the axis) that land back on the part's surface over the test turns.
/// Only the outer samples are judged: a turn barely moves those near the axis, and on a flat
/// part (a door, a lid) the faces' samples stay on the faces whatever its outline; the outline
/// is what a turn tests.
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

/// [`kept_fraction`] about the line along `axis` through `centre`.
fn kept_about_line(
    scene: &Scene,
    part: usize,
    points: &[DVec3],
    axis: DVec3,
    centre: DVec3,
    tolerance: f64,
) -> f64 {
    let radius = |p: &DVec3| (*p - centre).reject_from_normalized(axis).length();
    let farthest = points.iter().map(radius).fold(0.0, f64::max);
    let outer: Vec<DVec3> = points
        .iter()
        .filter(|p| radius(p) >= OUTER_RADIUS_FRACTION * farthest)
        .copied()
        .collect();
    TURNS_RAD
        .iter()
        .map(|&angle| {
            let turn = DQuat::from_axis_angle(axis, angle);
            let on = outer
                .iter()
                .filter(|p| {
                    let turned = centre + turn * (**p - centre);
                    scene.distance_to_surface_m(part, turned) <= tolerance
                })
                .count();
            on as f64 / outer.len().max(1) as f64
        })
        .fold(1.0, f64::min)
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
) -> Option<Spin> {
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
    Some(Spin {
        axis,
        centre: centre_about(points, axis),
        kept_fraction: kept,
        width_m,
        length_over_width: extent(axis) / width_m.max(1e-12),
    })
}
