//! The drive-to-limits test of one joint: in a fresh world at the rest pose, a velocity motor
//! with a bounded effort drives the joint to its lower, then its upper limit; then the motor is
//! released and the asset moves passively.
//!
//! The drive is a stiff velocity servo (it corrects velocity errors at 1000/s, or faster where
//! gravity would otherwise slow it by over 5 %: a short, slow lift) commanding 100 %
//! of the range per second toward the target (never more than closes the gap in one step), with
//! at most twice the moving group's weight times its lever arm (its weight for a prismatic
//! joint) plus the joint's own dry friction and damping at the drive speed: enough to lift a lid against gravity and to hit the
//! limit at speed, too little to push through a blocking contact. Criterion (all must hold to pass):
//! - each limit is reached within 2 % of the range (at least 0.005 rad or 1 mm) within its time
//!   budget (3 x the nominal traverse time + 0.5 s);
//! - all states stay finite and no body point moves faster than 10 object diagonals per second;
//! - every other joint that passed the at-rest test stays within 5 % of its range (at least
//!   twice the at-rest floor) of where it started: it is not kicked;
//! - after release, kinetic plus gravitational energy grows by at most 2 % of (moving weight x
//!   object diagonal): damping, friction, limits and contacts may only remove energy, so growth
//!   is an explosion in the making.

use std::time::Instant;

use uniphys_geometry::TriMesh;
use uniphys_types::{AssetRecord, CheckOutcome, PartId};

use crate::model::JointModel;
use crate::report::{DriveMetrics, Verdict};
use crate::scene::Scene;
use crate::trace::JointTrace;
use crate::{DynamicParams, SimulateResult};

/// Everything the drive test of one joint needs besides the record.
pub(crate) struct DriveSetup<'a> {
    /// The record (validated).
    pub record: &'a AssetRecord,
    /// Colliders by part position.
    pub colliders: &'a [Vec<TriMesh>],
    /// Excluded contact pairs.
    pub excluded_pairs: &'a [(PartId, PartId)],
    /// All movable joints.
    pub models: &'a [JointModel],
    /// Which joints passed the at-rest test (only those are judged for kicks).
    pub rest_passed: &'a [bool],
    /// Object diagonal, m.
    pub diagonal_m: f64,
    /// Mass of all non-root parts, kg.
    pub moving_mass_kg: f64,
}

/// Runs the drive test of `setup.models[driven]`.
pub(crate) fn run_drive(
    setup: &DriveSetup<'_>,
    driven: usize,
    params: &DynamicParams,
) -> SimulateResult<(DriveMetrics, f64)> {
    let started = Instant::now();
    let model = &setup.models[driven];
    let mut scene = Scene::build(
        setup.record,
        setup.colliders,
        setup.excluded_pairs,
        params,
        setup.diagonal_m,
    )?;
    let dt = params.dt_s();
    let speed = params.drive_speed_fraction_of_range_per_s * model.span();
    let budget_s = params.drive_time_multiple / params.drive_speed_fraction_of_range_per_s
        + params.drive_time_slack_s;
    let reach_tol = model.tolerance(params, params.reach_fraction_of_range, 1.0);
    let speed_bound = params.max_speed_diagonals_per_s * setup.diagonal_m;
    let mut others: Vec<(usize, JointTrace, f64)> = setup
        .models
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != driven && setup.rest_passed[*k])
        .map(|(k, m)| {
            // The drive starts at the rest pose, where every coordinate is 0.
            (
                k,
                JointTrace::new(0.0),
                m.tolerance(params, params.kick_fraction_of_range, 2.0),
            )
        })
        .collect();
    let mut watch = Watch {
        finite: true,
        max_point_speed_m_per_s: 0.0,
    };
    let targets = [model.lower, model.upper];
    let mut target_errors = [f64::NAN; 2];
    let mut times = [None; 2];
    let steps_per_target = (budget_s / dt).ceil() as usize;
    'targets: for (t, &target) in targets.iter().enumerate() {
        let mut elapsed_s = 0.0;
        for _ in 0..=steps_per_target {
            let (q, _) = scene
                .joint_state(model.joint_index)
                .unwrap_or((f64::NAN, f64::NAN));
            let error = target - q;
            target_errors[t] = error.abs();
            if !error.is_finite() {
                watch.finite = false;
                break 'targets;
            }
            if error.abs() <= reach_tol {
                times[t] = Some(elapsed_s);
                break;
            }
            if elapsed_s >= budget_s {
                break;
            }
            // Full speed, but never more than what closes the gap in one step.
            let command = error.signum() * speed.min(error.abs() / dt);
            scene.set_drive(
                model.joint_index,
                Some((command, model.drive_max_effort)),
                model.drive_gain_per_s,
            );
            if !scene.step() {
                watch.finite = false;
                break 'targets;
            }
            elapsed_s += dt;
            if !watch.observe(&scene, setup.models, &mut others).finite {
                break 'targets;
            }
        }
    }
    scene.set_drive(model.joint_index, None, model.drive_gain_per_s);
    let energy_start = scene.body_state().energy_j;
    let mut energy_max = energy_start;
    if watch.finite {
        let release_steps = (params.release_duration_s / dt).ceil() as usize;
        for _ in 0..release_steps {
            if !scene.step() {
                watch.finite = false;
                break;
            }
            let state = watch.observe(&scene, setup.models, &mut []);
            energy_max = energy_max.max(state.energy_j);
            if !state.finite {
                break;
            }
        }
    }
    let energy_gain = energy_max - energy_start;
    let energy_tolerance = params.energy_gain_fraction
        * setup.moving_mass_kg
        * params.gravity_m_per_s2
        * setup.diagonal_m
        + 1e-9;
    let (max_kick_ratio, most_kicked) = others
        .iter()
        .map(|(k, trace, tol)| (trace.max_drift / tol, *k))
        .fold((0.0, None), |(best, who), (ratio, k)| {
            if ratio > best {
                (ratio, Some(k))
            } else {
                (best, who)
            }
        });
    let max_kick_ratio = if others.iter().all(|(_, t, _)| t.finite) {
        max_kick_ratio
    } else {
        f64::INFINITY
    };

    let unit = model.unit();
    let mut reasons = Vec::new();
    let (finite, max_point_speed) = (watch.finite, watch.max_point_speed_m_per_s);
    if !finite {
        reasons.push("drive: the simulation produced non-finite states".to_owned());
    }
    if max_point_speed > speed_bound {
        reasons.push(format!(
            "drive: a body point reached {max_point_speed:.3} m/s (bound {speed_bound:.3} m/s): explodes"
        ));
    }
    for (t, name) in ["lower", "upper"].iter().enumerate() {
        if times[t].is_none() {
            reasons.push(format!(
                "drive: does not reach the {name} target {:.4} {unit} within {budget_s:.2} s (off by {:.4} {unit}; blocked by a contact, or effort bound {:.3} {} too small)",
                targets[t],
                target_errors[t],
                model.drive_max_effort,
                model.effort_unit().replace('_', " ")
            ));
        }
    }
    if max_kick_ratio > 1.0 {
        let who = most_kicked.map_or("another joint".to_owned(), |k| {
            format!("joint {}", setup.models[k].name)
        });
        reasons.push(format!(
            "drive: kicks {who} by {max_kick_ratio:.2} times its tolerance"
        ));
    }
    if energy_gain > energy_tolerance {
        reasons.push(format!(
            "release: mechanical energy grows by {energy_gain:.4} J (> {energy_tolerance:.4} J): unstable"
        ));
    }
    let outcome = if reasons.is_empty() {
        CheckOutcome::Pass
    } else {
        CheckOutcome::Fail
    };
    let metrics = DriveMetrics {
        targets,
        target_errors,
        times_to_reach_s: times,
        budget_s,
        max_effort: model.drive_max_effort,
        max_point_speed_m_per_s: max_point_speed,
        speed_bound_m_per_s: speed_bound,
        max_kick_ratio,
        most_kicked_joint: most_kicked.map(|k| setup.models[k].name.clone()),
        energy_gain_after_release_j: energy_gain,
        energy_tolerance_j: energy_tolerance,
        verdict: Verdict { outcome, reasons },
    };
    Ok((metrics, started.elapsed().as_secs_f64() * 1e3))
}

/// Object-wide watch over a drive: finiteness and the fastest body point.
struct Watch {
    finite: bool,
    max_point_speed_m_per_s: f64,
}

impl Watch {
    /// Samples the scene after a step; updates the kick traces of the other joints.
    fn observe(
        &mut self,
        scene: &Scene,
        models: &[JointModel],
        others: &mut [(usize, JointTrace, f64)],
    ) -> crate::scene::BodyState {
        let state = scene.body_state();
        self.finite &= state.finite;
        self.max_point_speed_m_per_s = self
            .max_point_speed_m_per_s
            .max(state.max_point_speed_m_per_s);
        for (k, trace, tol) in others.iter_mut() {
            let m = &models[*k];
            let (q, qd) = scene
                .joint_state(m.joint_index)
                .unwrap_or((f64::NAN, f64::NAN));
            trace.record(q, qd, *tol, f64::INFINITY);
        }
        state
    }
}
