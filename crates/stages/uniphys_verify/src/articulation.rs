//! Articulation verification of a whole asset: every movable joint swept, failures corrected or
//! reported.

use std::collections::BTreeMap;

use uniphys_geometry::parallel_map;
use uniphys_types::{CheckOutcome, CheckResult, Joint, ReportSection};

use crate::VerifyResult;
use crate::correct::correct_failed;
use crate::fit;
use crate::scene::{Scene, moving_group};
use crate::sweep::{SweepMetrics, sweep};
use crate::sweep_params::SweepParams;

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
/// variant passes it fails with the sweep's reasons. Joints declared by the input (provenance
/// `input`) are never changed: their failures are reported as they are.
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
    let movable: Vec<usize> = (0..joints.len())
        .filter(|&i| joints[i].kind.is_movable())
        .collect();
    // Joints are judged independently against the same scene, on all cores.
    let judged = parallel_map(&movable, |&i| {
        verify_joint(scene, joints, i, params, correct)
    });
    for (&i, result) in movable.iter().zip(judged) {
        let JointVerdict {
            correction,
            outcome,
            message,
            metrics,
            misfit: _,
        } = result?;
        let subject = format!("joint {}", joints[i].name);
        if let Some((joint, change)) = correction {
            out.corrections
                .push(format!("joint {:?}: {change}", joints[i].name));
            out.joints[i] = joint;
        }
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

/// Whether the joint was declared by the input file.
fn declared(joint: &Joint) -> bool {
    matches!(joint.provenance, uniphys_types::Provenance::Input { .. })
}

/// The verdict on one joint: the correction (if one replaced it), the outcome, the message and
/// the metrics of the sweep that decided.
#[derive(Debug, Clone, PartialEq)]
pub struct JointVerdict {
    /// The joint that replaces the given one and what was changed, when a correction passed.
    pub correction: Option<(Joint, String)>,
    /// Pass, Warn (corrected) or Fail.
    pub outcome: CheckOutcome,
    /// Why, for the report.
    pub message: String,
    /// The sweep that decided (the correction's when there is one).
    pub metrics: SweepMetrics,
    /// How badly the deciding joint fits the parts it moves (0: perfectly; a hinge along its
    /// parent and across from the handle, a spin about the part's round axis).
    pub misfit: f64,
}

/// Sweeps movable joint `joints[i]` (its child and what hangs below it move) and, if it fails
/// and `correct` is set and the input did not declare it, tries to correct it.
///
/// Errors: a part index out of range, a joint without limits (other than continuous).
pub fn verify_joint(
    scene: &Scene,
    joints: &[Joint],
    i: usize,
    params: &SweepParams,
    correct: bool,
) -> VerifyResult<JointVerdict> {
    let joint = &joints[i];
    let moving = moving_group(joints, joint.child);
    let metrics = sweep(scene, joint, &moving, params)?;
    let misfit = fit::misfit(scene, joint, &moving, &scene.points_of(&moving), &metrics);
    let reasons = metrics.failures(params);
    if reasons.is_empty() {
        let message = format!("{} steps without failure", metrics.steps);
        return Ok(JointVerdict {
            correction: None,
            outcome: CheckOutcome::Pass,
            message,
            metrics,
            misfit,
        });
    }
    if declared(joint) {
        let message = format!(
            "{}; declared by the input: reported, kept as given",
            reasons.join("; ")
        );
        return Ok(JointVerdict {
            correction: None,
            outcome: CheckOutcome::Fail,
            message,
            metrics,
            misfit,
        });
    }
    if correct && let Some(fix) = correct_failed(scene, joint, &moving, params, &metrics)? {
        let message = format!("{}; corrected: {}", reasons.join("; "), fix.change);
        return Ok(JointVerdict {
            correction: Some((fix.joint, fix.change)),
            outcome: CheckOutcome::Warn,
            message,
            metrics: fix.metrics,
            misfit: fix.misfit,
        });
    }
    let suffix = if correct {
        "; no correction passed"
    } else {
        ""
    };
    let message = format!("{}{suffix}", reasons.join("; "));
    Ok(JointVerdict {
        correction: None,
        outcome: CheckOutcome::Fail,
        message,
        metrics,
        misfit,
    })
}
