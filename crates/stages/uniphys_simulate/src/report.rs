//! The result of the dynamic check: metrics and a verdict with reasons per movable joint, and
//! its conversion into a `report.json` section.

use std::collections::BTreeMap;

use uniphys_types::{CheckOutcome, CheckResult, JointKind, ReportSection};

/// Name of the report section and of its checks.
pub const SECTION_NAME: &str = "dynamics";

/// An outcome with the reasons behind it (empty for a plain pass).
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// Pass, warn or fail.
    pub outcome: CheckOutcome,
    /// Why, one sentence each.
    pub reasons: Vec<String>,
}

impl Verdict {
    /// A pass without remarks.
    #[must_use]
    pub fn pass() -> Self {
        Self {
            outcome: CheckOutcome::Pass,
            reasons: Vec::new(),
        }
    }

    /// The worse of two verdicts (fail > warn > pass), keeping the reasons of both.
    #[must_use]
    pub fn combine(mut self, other: &Verdict) -> Self {
        let rank = |o: CheckOutcome| match o {
            CheckOutcome::Fail => 3,
            CheckOutcome::Warn => 2,
            CheckOutcome::Pass => 1,
            CheckOutcome::Skipped => 0,
        };
        if rank(other.outcome) > rank(self.outcome) {
            self.outcome = other.outcome;
        }
        self.reasons.extend(other.reasons.iter().cloned());
        self
    }
}

/// What a joint did in the at-rest test. Coordinates in rad (rotational) or m (prismatic).
#[derive(Debug, Clone, PartialEq)]
pub struct RestMetrics {
    /// Largest `|q - q0|`.
    pub max_drift: f64,
    /// The drift allowed.
    pub tolerance: f64,
    /// Largest `|dq/dt|`, per second.
    pub max_speed_per_s: f64,
    /// Coordinate at the end.
    pub final_q: f64,
    /// Velocity at the end, per second.
    pub final_speed_per_s: f64,
    /// Velocity reversals above the settle speed (swinging or bouncing).
    pub reversals: u32,
    /// Static gravity load on the joint at the rest pose (N m or N, signed).
    pub gravity_load: f64,
    /// The joint's dry friction (N m or N).
    pub friction: f64,
    /// Verdict of the test.
    pub verdict: Verdict,
}

/// What a joint did when driven to its limits. Coordinates in rad or m.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveMetrics {
    /// Targets (lower, upper): the limits, or -pi/2 and pi/2 for a continuous joint.
    pub targets: [f64; 2],
    /// Final distance to each target when its drive ended.
    pub target_errors: [f64; 2],
    /// Time to reach each target, s (`None`: not reached within the budget).
    pub times_to_reach_s: [Option<f64>; 2],
    /// Time budget per target, s.
    pub budget_s: f64,
    /// Bound on the drive's effort (N m or N).
    pub max_effort: f64,
    /// Largest speed of any point of any body during drive and release, m/s.
    pub max_point_speed_m_per_s: f64,
    /// The speed bound, m/s.
    pub speed_bound_m_per_s: f64,
    /// Largest motion of another joint relative to its kick tolerance (<= 1 is fine), and
    /// that joint's name.
    pub max_kick_ratio: f64,
    /// The joint behind `max_kick_ratio`, if any other joint was judged.
    pub most_kicked_joint: Option<String>,
    /// Growth of mechanical energy (kinetic + gravitational) after the drive was released, J.
    pub energy_gain_after_release_j: f64,
    /// The growth allowed, J.
    pub energy_tolerance_j: f64,
    /// Verdict of the test.
    pub verdict: Verdict,
}

/// Metrics and verdict of one movable joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointDynamics {
    /// Joint name.
    pub joint: String,
    /// Joint kind.
    pub kind: JointKind,
    /// At-rest test.
    pub rest: RestMetrics,
    /// Drive-to-limits test.
    pub drive: DriveMetrics,
    /// Wall-clock time of this joint's drive test, ms.
    pub drive_time_ms: f64,
    /// Overall verdict (the worse of the two tests).
    pub verdict: Verdict,
}

impl JointDynamics {
    /// Report subject, `joint <name>`.
    #[must_use]
    pub fn subject(&self) -> String {
        format!("joint {}", self.joint)
    }

    /// The numbers behind the verdict, named with their unit; all of them depend only on the
    /// asset, never on how long the check took.
    #[must_use]
    pub fn metrics(&self) -> BTreeMap<String, f64> {
        let (u, e) = if self.kind == JointKind::Prismatic {
            ("m", "n")
        } else {
            ("rad", "n_m")
        };
        let r = &self.rest;
        let d = &self.drive;
        let mut m = BTreeMap::new();
        let mut put = |k: String, v: f64| {
            m.insert(k, v);
        };
        put(format!("rest_max_drift_{u}"), r.max_drift);
        put(format!("rest_tolerance_{u}"), r.tolerance);
        put(format!("rest_max_speed_{u}_per_s"), r.max_speed_per_s);
        put(format!("rest_final_speed_{u}_per_s"), r.final_speed_per_s);
        put("rest_reversals".into(), f64::from(r.reversals));
        put(format!("rest_gravity_load_{e}"), r.gravity_load);
        put(format!("joint_friction_{e}"), r.friction);
        for (k, name) in ["lower", "upper"].iter().enumerate() {
            put(format!("drive_{name}_error_{u}"), d.target_errors[k]);
            if let Some(t) = d.times_to_reach_s[k] {
                put(format!("drive_{name}_time_s"), t);
            }
        }
        put("drive_budget_s".into(), d.budget_s);
        put(format!("drive_max_effort_{e}"), d.max_effort);
        put(
            "drive_max_point_speed_m_per_s".into(),
            d.max_point_speed_m_per_s,
        );
        put("drive_speed_bound_m_per_s".into(), d.speed_bound_m_per_s);
        put("drive_max_kick_ratio".into(), d.max_kick_ratio);
        put(
            "release_energy_gain_j".into(),
            d.energy_gain_after_release_j,
        );
        put("release_energy_tolerance_j".into(), d.energy_tolerance_j);
        // No wall time here: the report is an output file, the same bytes on every run (a
        // retried stage may not write different ones); `drive_time_ms` serves benchmarks.
        m
    }
}

/// Result of [`crate::check_dynamics`].
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicReport {
    /// One entry per movable joint, in record order.
    pub joints: Vec<JointDynamics>,
    /// Wall-clock time of the at-rest test (all joints at once), ms.
    pub rest_time_ms: f64,
    /// Wall-clock time of the whole check, ms.
    pub total_time_ms: f64,
    /// Things the check had to leave out (degenerate hulls).
    pub notes: Vec<String>,
}

impl DynamicReport {
    /// Whether no joint failed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.joints
            .iter()
            .all(|j| j.verdict.outcome != CheckOutcome::Fail)
    }

    /// The joint named `name`.
    #[must_use]
    pub fn joint(&self, name: &str) -> Option<&JointDynamics> {
        self.joints.iter().find(|j| j.joint == name)
    }

    /// The `dynamics` section of `report.json`: one check per movable joint.
    #[must_use]
    pub fn to_report_section(&self) -> ReportSection {
        ReportSection {
            name: SECTION_NAME.into(),
            checks: self
                .joints
                .iter()
                .map(|j| CheckResult {
                    check: SECTION_NAME.into(),
                    subject: j.subject(),
                    outcome: j.verdict.outcome,
                    message: if j.verdict.reasons.is_empty() {
                        "stays at rest; reaches both limits; no energy gain after release".into()
                    } else {
                        j.verdict.reasons.join("; ")
                    },
                })
                .collect(),
        }
    }

    /// The metrics by subject (`joint <name>`), then by name with unit, in the shape of
    /// `VerificationReport::metrics`.
    #[must_use]
    pub fn metrics(&self) -> BTreeMap<String, BTreeMap<String, f64>> {
        self.joints
            .iter()
            .map(|j| (j.subject(), j.metrics()))
            .collect()
    }
}
