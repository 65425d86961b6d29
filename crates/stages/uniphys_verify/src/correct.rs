//! Feedback correction of a joint that failed its sweep: reversed range, then the other candidate
//! axes and pivots, then a smaller range; the first variant that passes is kept.

use uniphys_geometry::{DVec3, box_axes};
use uniphys_types::{Joint, JointKind, JointLimits};

use crate::VerifyResult;
use crate::candidates::articulation_candidates;

use crate::scene::Scene;
use crate::sweep::{SweepMetrics, SweepParams, sweep};

/// A corrected joint, what was changed, and the sweep it passed.
#[derive(Debug, Clone, PartialEq)]
pub struct Correction {
    /// The joint that passed.
    pub joint: Joint,
    /// What was changed, for the report.
    pub change: String,
    /// The passing sweep.
    pub metrics: SweepMetrics,
}

/// Steps of the quick pre-screen sweep run before a full one.
const SCREEN_STEPS: usize = 24;
/// Most variants screened per joint, in the order of [`variants`] (bounds the time spent on
/// one joint: every range reversal and the nearest axes and pivots come first).
const MAX_VARIANTS: usize = 24;

/// Variants of `joint` in the order they are tried.
fn variants(
    scene: &Scene,
    joint: &Joint,
    moving: &[usize],
    params: &SweepParams,
) -> Vec<(Joint, String)> {
    let mut out = Vec::new();
    let Some(limits) = joint.limits else {
        return out;
    };
    let with = |axis: DVec3, pivot: DVec3, lower: f64, upper: f64| {
        let mut j = joint.clone();
        j.axis_in_object = axis.to_array();
        j.pivot_in_object_m = pivot.to_array();
        j.limits = Some(JointLimits { lower, upper });
        j
    };
    let axis = DVec3::from_array(joint.axis_in_object);
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    let (lo, hi) = (limits.lower, limits.upper);
    out.push((
        with(axis, pivot, -hi, -lo),
        format!("range reversed to [{:.4}, {:.4}]", -hi, -lo),
    ));
    let moving_points = scene.points_of(moving);
    let parent_points = &scene.samples[joint.parent.0 as usize];
    if let Ok(c) = articulation_candidates(
        &moving_points,
        parent_points,
        box_axes(&scene.points_of(&[joint.child.0 as usize])),
        scene.diagonal_m,
        &params.patch,
        params.seed,
    ) {
        let mut axes: Vec<(usize, DVec3)> = c.axes.iter().copied().enumerate().collect();
        axes.sort_by(|a, b| angle(a.1, axis).total_cmp(&angle(b.1, axis)));
        for (k, candidate) in axes.into_iter().filter(|(_, a)| angle(*a, axis) > 1e-2) {
            for sign in [1.0, -1.0] {
                let a = candidate * sign;
                out.push((
                    with(a, pivot, lo, hi),
                    format!(
                        "axis changed to candidate {k} ({:.3}, {:.3}, {:.3})",
                        a.x, a.y, a.z
                    ),
                ));
            }
        }
        if joint.kind != JointKind::Prismatic {
            let mut pivots: Vec<(usize, DVec3)> = c.pivots.iter().copied().enumerate().collect();
            pivots.sort_by(|a, b| a.1.distance(pivot).total_cmp(&b.1.distance(pivot)));
            for (k, p) in pivots.into_iter().filter(|(_, p)| p.distance(pivot) > 1e-6) {
                for (l, h) in [(lo, hi), (-hi, -lo)] {
                    out.push((
                        with(axis, p, l, h),
                        format!(
                            "pivot changed to candidate {k} ({:.4}, {:.4}, {:.4}), range [{l:.4}, {h:.4}]",
                            p.x, p.y, p.z
                        ),
                    ));
                }
            }
        }
    }
    for fraction in [0.5, 0.25] {
        let (l, h) = (lo * fraction, hi * fraction);
        out.push((
            with(axis, pivot, l, h),
            format!("range reduced to [{l:.4}, {h:.4}]"),
        ));
    }
    out
}

/// Angle between two lines (sign ignored), radians.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .abs()
        .clamp(0.0, 1.0)
        .acos()
}

/// Tries the variants of a failed `joint` (moving the parts in `moving`) and returns the first
/// whose sweep passes, or `None` if none does. Each variant is screened with a short sweep
/// before the full one; at most 24 variants are tried.
pub fn correct_joint(
    scene: &Scene,
    joint: &Joint,
    moving: &[usize],
    params: &SweepParams,
) -> VerifyResult<Option<Correction>> {
    let screen = SweepParams {
        steps: SCREEN_STEPS,
        ..*params
    };
    for (candidate, change) in variants(scene, joint, moving, params)
        .into_iter()
        .take(MAX_VARIANTS)
    {
        if !sweep(scene, &candidate, moving, &screen)?
            .failures(&screen)
            .is_empty()
        {
            continue;
        }
        let metrics = sweep(scene, &candidate, moving, params)?;
        if metrics.failures(params).is_empty() {
            return Ok(Some(Correction {
                joint: candidate,
                change,
                metrics,
            }));
        }
    }
    Ok(None)
}
