//! The at-rest test: gravity on, every joint passive with its damping and dry friction, the root
//! fixed; does anything move on its own from the exported rest pose?
//!
//! Criterion, per movable joint (`tol` = 2 % of the range, at least 0.005 rad or 1 mm):
//! - **fail** if any state turns non-finite or any body point exceeds the speed bound
//!   (explosion), or if the rest pose lies outside the limits by more than `tol`;
//! - **pass** if the coordinate never drifts more than `tol` from the rest pose (this includes a
//!   lid resting closed on its limit: the limit holds it);
//! - **warn** if it drifts, but gravity explains it: the static gravity load at the rest pose
//!   exceeds the joint's dry friction (by 5 %), the first motion is in the direction of that
//!   load, and the joint neither swings nor bounces (no velocity reversal above the settle speed
//!   of 5 % of the range per second). An open lid whose friction cannot hold it falls closed
//!   in every simulator; the asset is usable, but its rest pose is not an equilibrium;
//! - **fail** otherwise: it moves although its friction holds the gravity load (a contact push
//!   or a numerical defect such as a bad inertia), moves against gravity, or swings or bounces
//!   (an under-damped pendulum; a limit is inelastic, so a lid that falls onto it stops).

use crate::DynamicParams;
use crate::model::JointModel;
use crate::report::{RestMetrics, Verdict};
use crate::scene::Scene;
use crate::trace::JointTrace;
use uniphys_types::CheckOutcome;

/// Object-wide facts of a phase.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhaseSummary {
    /// Largest body point speed, m/s.
    pub max_point_speed_m_per_s: f64,
    /// The speed bound, m/s.
    pub speed_bound_m_per_s: f64,
    /// Whether all states stayed finite.
    pub finite: bool,
}

/// Runs the at-rest test on `scene` (freshly built, at the rest pose) and judges every joint of
/// `models`.
pub(crate) fn run_rest(
    scene: &mut Scene,
    models: &[JointModel],
    params: &DynamicParams,
    speed_bound_m_per_s: f64,
) -> Vec<RestMetrics> {
    // Joint coordinates are 0 at the exported rest pose by construction.
    let mut traces: Vec<JointTrace> = models.iter().map(|_| JointTrace::new(0.0)).collect();
    let mut summary = PhaseSummary {
        max_point_speed_m_per_s: 0.0,
        speed_bound_m_per_s,
        finite: true,
    };
    let steps = (params.rest_duration_s * params.rate_hz).ceil() as usize;
    for _ in 0..steps {
        if !scene.step() {
            summary.finite = false;
            break;
        }
        let state = scene.body_state();
        summary.finite &= state.finite;
        summary.max_point_speed_m_per_s = summary
            .max_point_speed_m_per_s
            .max(state.max_point_speed_m_per_s);
        for (model, trace) in models.iter().zip(&mut traces) {
            let (q, qd) = scene
                .joint_state(model.joint_index)
                .unwrap_or((f64::NAN, f64::NAN));
            trace.record(q, qd, model.rest_tolerance, settle_speed(model, params));
        }
        if !summary.finite {
            break;
        }
    }
    models
        .iter()
        .zip(&traces)
        .map(|(model, trace)| judge_rest(model, trace, &summary, params))
        .collect()
}

/// Speed below which a joint counts as settled, per second.
pub(crate) fn settle_speed(model: &JointModel, params: &DynamicParams) -> f64 {
    model.tolerance(params, params.settle_speed_fraction_of_range_per_s, 1.0)
}

/// The criterion of the module documentation.
pub(crate) fn judge_rest(
    model: &JointModel,
    trace: &JointTrace,
    summary: &PhaseSummary,
    params: &DynamicParams,
) -> RestMetrics {
    let tol = model.rest_tolerance;
    let unit = model.unit();
    let effort = model.effort_unit().replace('_', " ");
    let mut fails: Vec<String> = Vec::new();
    let mut warns: Vec<String> = Vec::new();
    if !(summary.finite && trace.finite) {
        fails.push("at rest: the simulation produced non-finite states".into());
    } else if summary.max_point_speed_m_per_s > summary.speed_bound_m_per_s {
        fails.push(format!(
            "at rest: a body point reached {:.3} m/s (bound {:.3} m/s): explodes",
            summary.max_point_speed_m_per_s, summary.speed_bound_m_per_s
        ));
    }
    if model.limited && model.distance_to_limit(trace.q_start) < -tol {
        fails.push(format!(
            "at rest: the rest pose q0 = {:.4} {unit} lies outside the limits [{:.4}, {:.4}]",
            trace.q_start, model.lower, model.upper
        ));
    }
    let moved = trace.max_drift > tol;
    if fails.is_empty() && moved {
        let gravity = model.gravity_load;
        let gravity_wins = gravity.abs() > params.gravity_over_friction_margin * model.friction;
        let with_gravity = trace.first_move_sign == gravity.signum() && gravity != 0.0;
        if trace.reversals > 0 {
            fails.push(format!(
                    "at rest: swings ({} velocity reversals, drift {:.4} {unit} > {:.4}): damping too low for the gravity load {:.3} {effort}",
                    trace.reversals, trace.max_drift, tol, gravity
                ));
        } else if gravity_wins && with_gravity {
            let settled = trace.qd_end.abs() <= settle_speed(model, params);
            let at_limit = model.limited && model.distance_to_limit(trace.q_end).abs() <= tol;
            warns.push(format!(
                "at rest: moves {:.4} {unit} under gravity (load {:.3} {effort} > friction {:.3} {effort}), {}: the rest pose is not an equilibrium",
                trace.max_drift,
                gravity.abs(),
                model.friction,
                match (at_limit, settled) {
                    (true, true) => "settles on a limit",
                    (true, false) => "ends on a limit",
                    (false, true) => "settles inside the range",
                    (false, false) => "still moving at the end",
                }
            ));
        } else {
            fails.push(format!(
                "at rest: moves {:.4} {unit} (> {:.4}) although {}",
                trace.max_drift,
                tol,
                if gravity_wins {
                    format!("gravity pushes the other way (load {gravity:.3} {effort})")
                } else {
                    format!(
                        "friction {:.3} {effort} holds the gravity load {:.3} {effort}",
                        model.friction,
                        gravity.abs()
                    )
                }
            ));
        }
    }
    RestMetrics {
        max_drift: trace.max_drift,
        tolerance: tol,
        max_speed_per_s: trace.max_speed,
        final_q: trace.q_end,
        final_speed_per_s: trace.qd_end.abs(),
        reversals: trace.reversals,
        gravity_load: model.gravity_load,
        friction: model.friction,
        verdict: if !fails.is_empty() {
            Verdict {
                outcome: CheckOutcome::Fail,
                reasons: fails,
            }
        } else if !warns.is_empty() {
            Verdict {
                outcome: CheckOutcome::Warn,
                reasons: warns,
            }
        } else {
            Verdict::pass()
        },
    }
}

#[cfg(test)]
mod tests {
    use uniphys_types::JointKind;

    use super::*;

    /// A lid-like joint: range [0, 1.5] rad, tolerance 0.03 rad, gravity load -2 N m.
    fn lid(friction: f64) -> JointModel {
        JointModel {
            joint_index: 0,
            name: "lid".into(),
            kind: JointKind::Revolute,
            lower: 0.0,
            upper: 1.5,
            limited: true,
            friction,
            gravity_load: -2.0,
            drive_max_effort: 10.0,
            drive_gain_per_s: 1000.0,
            rest_tolerance: 0.03,
        }
    }

    fn calm() -> PhaseSummary {
        PhaseSummary {
            max_point_speed_m_per_s: 0.1,
            speed_bound_m_per_s: 10.0,
            finite: true,
        }
    }

    /// A trace through the given (q, qd) samples.
    fn trace(q0: f64, samples: &[(f64, f64)]) -> JointTrace {
        let mut t = JointTrace::new(q0);
        for &(q, qd) in samples {
            t.record(q, qd, 0.03, 0.075);
        }
        t
    }

    fn judge(model: &JointModel, t: &JointTrace, s: &PhaseSummary) -> RestMetrics {
        judge_rest(model, t, s, &DynamicParams::default())
    }

    #[test]
    fn drift_within_tolerance_passes() {
        let r = judge(
            &lid(0.0),
            &trace(0.0, &[(-0.01, -0.1), (-0.02, 0.0)]),
            &calm(),
        );
        assert_eq!(r.verdict.outcome, CheckOutcome::Pass, "{:?}", r.verdict);
    }

    #[test]
    fn falling_closed_under_gravity_onto_the_limit_warns() {
        // Rest pose open at 0.8 rad; gravity (-2 N m) beats friction (0.1 N m); lands on 0.
        let r = judge(
            &lid(0.1),
            &trace(0.8, &[(0.6, -1.0), (0.2, -2.0), (0.0, 0.0), (0.0, 0.0)]),
            &calm(),
        );
        assert_eq!(r.verdict.outcome, CheckOutcome::Warn, "{:?}", r.verdict);
        assert!(r.verdict.reasons[0].contains("settles on a limit"));
    }

    #[test]
    fn the_same_motion_fails_when_friction_should_hold_it() {
        let r = judge(
            &lid(5.0),
            &trace(0.8, &[(0.6, -1.0), (0.2, -2.0), (0.0, 0.0)]),
            &calm(),
        );
        assert_eq!(r.verdict.outcome, CheckOutcome::Fail, "{:?}", r.verdict);
        assert!(r.verdict.reasons[0].contains("holds the gravity load"));
    }

    #[test]
    fn moving_against_gravity_fails() {
        let r = judge(&lid(0.1), &trace(0.8, &[(0.9, 1.0), (1.0, 0.0)]), &calm());
        assert_eq!(r.verdict.outcome, CheckOutcome::Fail, "{:?}", r.verdict);
        assert!(r.verdict.reasons[0].contains("pushes the other way"));
    }

    #[test]
    fn swinging_fails_even_when_gravity_drives_it() {
        let r = judge(
            &lid(0.0),
            &trace(0.8, &[(0.5, -1.0), (0.3, -0.5), (0.4, 0.5), (0.6, 1.0)]),
            &calm(),
        );
        assert_eq!(r.verdict.outcome, CheckOutcome::Fail, "{:?}", r.verdict);
        assert_eq!(r.reversals, 1);
    }

    #[test]
    fn rest_pose_outside_the_limits_fails_even_without_motion() {
        let r = judge(&lid(0.1), &trace(-0.2, &[(-0.2, 0.0)]), &calm());
        assert_eq!(r.verdict.outcome, CheckOutcome::Fail, "{:?}", r.verdict);
        assert!(r.verdict.reasons[0].contains("outside the limits"));
    }

    #[test]
    fn non_finite_state_or_speeding_body_fails() {
        let still = trace(0.0, &[(0.0, 0.0)]);
        let nan = PhaseSummary {
            finite: false,
            ..calm()
        };
        let fast = PhaseSummary {
            max_point_speed_m_per_s: 50.0,
            ..calm()
        };
        assert_eq!(
            judge(&lid(0.1), &still, &nan).verdict.outcome,
            CheckOutcome::Fail
        );
        let r = judge(&lid(0.1), &still, &fast);
        assert_eq!(r.verdict.outcome, CheckOutcome::Fail);
        assert!(r.verdict.reasons[0].contains("explodes"));
    }
}
