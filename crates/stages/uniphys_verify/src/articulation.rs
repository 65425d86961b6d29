//! Articulation verification of a whole asset: every movable joint swept, failures corrected or
//! reported.

use std::collections::BTreeMap;

use uniphys_types::{CheckOutcome, CheckResult, Joint, ReportSection};

use crate::VerifyResult;
use crate::correct::correct_joint;
use crate::scene::{Scene, moving_group};
use crate::sweep::{SweepParams, sweep};

/// The result of verifying the joints of an asset.
#[derive(Debug, Clone, PartialEq)]
pub struct ArticulationOutcome {
    /// The joints after correction (same order as given).
    pub joints: Vec<Joint>,
    /// Section `articulation` of the report: one check per movable joint.
    pub section: ReportSection,
    /// Sweep metrics by subject (`joint <name>`).
    pub metrics: BTreeMap<String, BTreeMap<String, f64>>,
    /// One line per corrected joint.
    pub corrections: Vec<String>,
}

impl ArticulationOutcome {
    /// Whether every movable joint passed, corrected or not.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.section.passed()
    }
}

/// Sweeps every movable joint; a joint that fails is corrected when `correct` is set (the first
/// passing variant replaces it, the change is reported as a warning), otherwise or when no
/// variant passes it fails with the sweep's reasons.
pub fn verify_articulation(
    scene: &Scene,
    joints: &[Joint],
    params: &SweepParams,
    correct: bool,
) -> VerifyResult<ArticulationOutcome> {
    let mut out = ArticulationOutcome {
        joints: joints.to_vec(),
        section: ReportSection {
            name: "articulation".into(),
            checks: Vec::new(),
        },
        metrics: BTreeMap::new(),
        corrections: Vec::new(),
    };
    for (i, joint) in joints.iter().enumerate() {
        if !joint.kind.is_movable() {
            continue;
        }
        let subject = format!("joint {}", joint.name);
        let moving = moving_group(joints, joint.child);
        let metrics = sweep(scene, joint, &moving, params)?;
        let reasons = metrics.failures(params);
        let (outcome, message, metrics) = if reasons.is_empty() {
            (
                CheckOutcome::Pass,
                format!("{} steps without failure", metrics.steps),
                metrics,
            )
        } else if let Some(fix) = correct
            .then(|| correct_joint(scene, joint, &moving, params))
            .transpose()?
            .flatten()
        {
            let message = format!("{}; corrected: {}", reasons.join("; "), fix.change);
            out.corrections
                .push(format!("joint {:?}: {}", joint.name, fix.change));
            out.joints[i] = fix.joint;
            (CheckOutcome::Warn, message, fix.metrics)
        } else {
            let suffix = if correct {
                "; no correction passed"
            } else {
                ""
            };
            (
                CheckOutcome::Fail,
                format!("{}{suffix}", reasons.join("; ")),
                metrics,
            )
        };
        out.metrics.insert(subject.clone(), metrics.as_map());
        out.section.checks.push(CheckResult {
            check: "articulation_sweep".into(),
            subject,
            outcome,
            message,
        });
    }
    Ok(out)
}
