//! The simulation-driven choice of a joint: enumerate joint hypotheses from the contact geometry
//! (candidate axes x candidate pivots x direction), sweep each one, keep the best by the
//! sweep's penalties plus simple priors.

use uniphys_geometry::{DVec3, box_axes, extent_along, parallel_map, projection_range};
use uniphys_types::{Joint, JointKind};
use uniphys_verify::{
    ArticulationCandidates, PatchParams, Scene, SweepMetrics, SweepParams, articulation_candidates,
    sweep,
};

use crate::articulate::builtin_joint;

/// Steps of each hypothesis sweep (the chosen joint is verified later with the full sweep).
pub(crate) const SCREEN_STEPS: usize = 16;
/// Surface samples per part in the hypothesis scene.
pub(crate) const SCREEN_SAMPLES: usize = 600;
/// Range of a hinged part, radians (opens a quarter turn).
const HINGE_RANGE_RAD: f64 = std::f64::consts::FRAC_PI_2;
/// Travel of a sliding part as a fraction of its length along the axis.
const SLIDE_TRAVEL_FRACTION: f64 = 0.8;

/// A scored joint hypothesis.
#[derive(Debug, Clone)]
pub(crate) struct Scored {
    pub(crate) joint: Joint,
    pub(crate) score: f64,
    pub(crate) metrics: SweepMetrics,
    pub(crate) hypotheses: usize,
}

/// What the search knows about the part being articulated.
pub(crate) struct Subject<'a> {
    pub(crate) child: usize,
    pub(crate) parent: usize,
    /// The child and the parts fixed to it.
    pub(crate) moving: &'a [usize],
    pub(crate) kind: JointKind,
}

/// Best hypothesis for `subject`, or `None` when the part does not touch its parent (no
/// candidates) or no hypothesis could be swept.
pub(crate) fn best_joint(scene: &Scene, subject: &Subject<'_>) -> Option<Scored> {
    let moving_points = scene.points_of(subject.moving);
    let parent_points = scene.points_of(&[subject.parent]);
    let child_points = scene.points_of(&[subject.child]);
    let part_axes = box_axes(&child_points);
    let candidates = articulation_candidates(
        &moving_points,
        &parent_points,
        part_axes,
        scene.diagonal_m,
        &PatchParams::default(),
        17,
    )
    .ok()?;
    let child_centre = mean(&child_points);
    let outward = child_centre - mean(&parent_points);
    let params = SweepParams {
        steps: SCREEN_STEPS,
        ..SweepParams::default()
    };
    let handles: Vec<DVec3> = subject
        .moving
        .iter()
        .filter(|&&p| p != subject.child)
        .map(|&p| mean(&scene.points_of(&[p])))
        .collect();
    let mut all = hypotheses(
        subject,
        &candidates,
        &child_points,
        &handles,
        part_axes,
        outward,
    );
    // Snapped pivots often land on the same hinge line: sweep each distinct line once (the
    // first keeps its prior). A line is its direction and its point nearest the object centre.
    let mut seen = std::collections::BTreeSet::new();
    let key = |j: &Joint| {
        let axis = DVec3::from_array(j.axis_in_object);
        let q = |x: f64| (x / (1e-3 * scene.diagonal_m)).round() as i64;
        let foot = if j.kind == JointKind::Prismatic {
            DVec3::ZERO
        } else {
            (DVec3::from_array(j.pivot_in_object_m) - scene.centre_m).reject_from_normalized(axis)
        };
        (
            axis.to_array().map(|a| (a * 1e4).round() as i64),
            foot.to_array().map(q),
        )
    };
    all.retain(|(j, _)| seen.insert(key(j)));
    let swept = parallel_map(&all, |(joint, prior)| {
        sweep(scene, joint, subject.moving, &params)
            .ok()
            .map(|m| (sweep_penalty(&m, scene.diagonal_m, &params) + prior, m))
    });
    let count = swept.iter().flatten().count();
    // The first hypothesis with the lowest score wins, so the choice does not depend on threads.
    let mut best: Option<Scored> = None;
    for ((joint, _), result) in all.into_iter().zip(swept) {
        let Some((score, metrics)) = result else {
            continue;
        };
        if best.as_ref().is_none_or(|b| score < b.score - 1e-9) {
            best = Some(Scored {
                joint,
                score,
                metrics,
                hypotheses: count,
            });
        }
    }
    best
}

/// The mean of the points (the origin for none).
pub(crate) fn mean(points: &[DVec3]) -> DVec3 {
    points.iter().sum::<DVec3>() / points.len().max(1) as f64
}

/// Penalty of a sweep: the moving surface passing through other parts (the verifier's
/// verdict, relative to its limit), interpenetration of the convex colliders (depth relative to
/// the tolerance, and how often; half weight, since hulls fill cavities), lost contact (heavier
/// for hinges), no contact at all.
fn sweep_penalty(m: &SweepMetrics, diagonal_m: f64, params: &SweepParams) -> f64 {
    let steps = m.steps.max(1) as f64;
    let tolerance = params.penetration_tolerance_fraction * diagonal_m;
    let crossing = 5.0 * (m.crossed_fraction / params.crossing_fraction_max).min(4.0);
    let depth = 0.5 * (m.max_penetration_growth_m / tolerance).min(10.0) + crossing;
    let penetrating = m.penetrating_steps as f64 / steps;
    let lost = m.lost_contact_steps as f64 / steps;
    let rotational = m.kind != JointKind::Prismatic;
    let no_contact = if m.initial_contact_points == 0 {
        10.0
    } else {
        0.0
    };
    depth + 2.5 * penetrating + if rotational { 5.0 } else { 2.0 } * lost + no_contact
}

/// Angle from `a` to the nearest of the part's principal axes (sign ignored), radians.
fn misalignment_rad(a: DVec3, part_axes: [DVec3; 3]) -> f64 {
    let best = part_axes.iter().map(|e| e.dot(a).abs()).fold(0.0, f64::max);
    best.clamp(0.0, 1.0).acos()
}

/// The pivot moved onto an edge of the part: across the axis within the contact plane to the
/// nearer side of the part, and along the contact normal to the face the part swings toward (a
/// door opening outward turns about its outer edge and clears its frame).
fn edge_pivot(
    pivot: DVec3,
    axis: DVec3,
    normal: DVec3,
    centre: DVec3,
    child_points: &[DVec3],
) -> Option<DVec3> {
    let u = normal.cross(axis);
    if u.length() < 1e-6 {
        return None;
    }
    let u = u.normalize();
    let range = |d: DVec3| projection_range(child_points, d);
    let (lo, hi) = range(u);
    let at = pivot.dot(u);
    let side = if (at - lo).abs() <= (hi - at).abs() {
        lo
    } else {
        hi
    };
    let across = pivot + u * (side - at);
    let n = normal.reject_from_normalized(axis).normalize_or_zero();
    let swing = axis.cross(centre - across).dot(n);
    let (lo, hi) = range(n);
    let face = if swing >= 0.0 { hi } else { lo };
    Some(across + n * (face - across.dot(n)))
}

/// All hypotheses for the subject's joint kind with their prior penalties:
/// - axes far from the part's principal axes (its edges) cost up to 0.5 (at 45 degrees);
/// - motion that brings the part's centre toward its parent's centre costs 0.3;
/// - hinges: an axis out of the contact plane costs up to 1, a hinge line through the middle of
///   the part up to 1.5, a hinge along a short edge of the part up to 0.2 (hinges run along the
///   long edge of lids and doors), a hinge line near a handle (a part carried by this one) up to 0.5.
fn hypotheses(
    subject: &Subject<'_>,
    candidates: &ArticulationCandidates,
    child_points: &[DVec3],
    handles: &[DVec3],
    part_axes: [DVec3; 3],
    outward: DVec3,
) -> Vec<(Joint, f64)> {
    let centre = mean(child_points);
    let longest = part_axes
        .iter()
        .map(|e| extent_along(child_points, *e))
        .fold(0.0, f64::max)
        .max(1e-12);
    let mut out = Vec::new();
    for (k, &axis) in candidates.axes.iter().enumerate() {
        for sign in [1.0, -1.0] {
            let a = axis * sign;
            let misaligned =
                0.5 * (misalignment_rad(a, part_axes) / std::f64::consts::FRAC_PI_4).min(1.0);
            if subject.kind == JointKind::Prismatic {
                let travel = SLIDE_TRAVEL_FRACTION * extent_along(child_points, a);
                let inward = if a.dot(outward) < 0.0 { 0.3 } else { 0.0 };
                let why = format!("sweep-selected slide along candidate axis {k}");
                out.push((
                    joint(subject, JointKind::Prismatic, a, centre, travel, why),
                    misaligned + inward,
                ));
                continue;
            }
            let off_plane = a.dot(candidates.contact_normal).abs();
            let short_edge = 0.2 * (1.0 - extent_along(child_points, a) / longest).max(0.0);
            for (l, &candidate) in candidates.pivots.iter().enumerate() {
                let snapped = edge_pivot(
                    candidate,
                    a,
                    candidates.contact_normal,
                    centre,
                    child_points,
                );
                for (pivot, how) in std::iter::once((candidate, ""))
                    .chain(snapped.map(|p| (p, " moved to the part's edge")))
                {
                    let reach = child_points
                        .iter()
                        .map(|p| (*p - pivot).reject_from_normalized(a).length())
                        .fold(0.0, f64::max);
                    if reach <= 0.0 {
                        continue;
                    }
                    let r = (centre - pivot).reject_from_normalized(a).length();
                    let through_middle = 1.5 * (1.0 - 2.0 * r / reach).max(0.0);
                    let near_handle = handles
                        .iter()
                        .map(|h| {
                            0.5 * (1.0 - (*h - pivot).reject_from_normalized(a).length() / reach)
                                .max(0.0)
                        })
                        .fold(0.0, f64::max);
                    let velocity = a.cross(centre - pivot);
                    let inward = if velocity.dot(outward) < 0.0 {
                        0.3
                    } else {
                        0.0
                    };
                    let why = format!(
                        "sweep-selected hinge on candidate axis {k} through candidate pivot {l}{how}"
                    );
                    out.push((
                        joint(subject, JointKind::Revolute, a, pivot, HINGE_RANGE_RAD, why),
                        misaligned + off_plane + short_edge + through_middle + near_handle + inward,
                    ));
                }
            }
        }
    }
    out
}

fn joint(
    subject: &Subject<'_>,
    kind: JointKind,
    axis: DVec3,
    pivot: DVec3,
    upper: f64,
    why: String,
) -> Joint {
    builtin_joint(
        kind,
        (subject.parent, subject.child),
        axis,
        pivot,
        Some(upper),
        why,
    )
}
