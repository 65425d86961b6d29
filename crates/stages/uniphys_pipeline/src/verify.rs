//! The verify stage: intrinsic checks (levels 0-4), articulation sweeps with feedback
//! correction, and the dynamic check in rapier, on the grounded record.

use std::collections::BTreeMap;

use uniphys_geometry::TriMesh;
use uniphys_simulate::{DynamicParams, check_dynamics};
use uniphys_types::{AssetRecord, CheckOutcome, PartId, VERIFIED_VERSION, VerifiedAsset};
use uniphys_verify::{Scene, SweepParams, verify_articulation, verify_intrinsic};

use crate::PipelineResult;

/// Parameters of the verify stage.
#[derive(Debug, Clone, PartialEq)]
pub struct VerifyOptions {
    /// Sweep parameters (steps, thresholds relative to the object).
    pub sweep: SweepParams,
    /// Surface samples per part for contact measurement.
    pub samples_per_part: usize,
    /// Try to correct joints that fail their sweep.
    pub correct: bool,
    /// Parameters of the dynamic check; `None` skips it.
    pub dynamics: Option<DynamicParams>,
}

impl Default for VerifyOptions {
    /// The default sweep (200 steps), 1500 samples per part, correction on, the default
    /// dynamic check.
    fn default() -> Self {
        Self {
            sweep: SweepParams::default(),
            samples_per_part: 1500,
            correct: true,
            dynamics: Some(DynamicParams::default()),
        }
    }
}

/// Runs intrinsic and articulation verification; failed joints are corrected when a variant
/// passes (the record then carries the corrected joint); then the dynamic check on the corrected
/// record, ignoring contacts between `touching_pairs` as the exported MJCF does.
pub(crate) fn verify(
    mut record: AssetRecord,
    meshes: &[TriMesh],
    colliders: &[Vec<TriMesh>],
    touching_pairs: Vec<(PartId, PartId)>,
    options: &VerifyOptions,
) -> PipelineResult<VerifiedAsset> {
    let intrinsic = verify_intrinsic(&record);
    let scene = Scene::new(meshes, colliders, options.samples_per_part)?;
    let articulation =
        verify_articulation(&scene, &record.joints, &options.sweep, options.correct)?;
    record.joints = articulation.joints.clone();
    record.validate()?;
    let joints_swept = articulation.section.checks.len();
    let joints_passed = articulation
        .section
        .checks
        .iter()
        .filter(|c| c.outcome != CheckOutcome::Fail)
        .count();
    let mut metrics: BTreeMap<String, BTreeMap<String, f64>> = BTreeMap::new();
    merge_prefixed(&mut metrics, &articulation.metrics, "sweep_");
    metrics.insert("object".to_owned(), intrinsic.metrics.clone());
    let mut sections = vec![intrinsic.section.clone(), articulation.section];
    if let Some(params) = &options.dynamics {
        let dynamics = check_dynamics(&record, colliders, &touching_pairs, params)?;
        merge_prefixed(&mut metrics, &dynamics.metrics(), "dynamics_");
        sections.push(dynamics.to_report_section());
    }
    Ok(VerifiedAsset {
        version: VERIFIED_VERSION,
        record,
        sections,
        metrics,
        corrections: articulation.corrections,
        touching: touching_pairs,
        joints_swept,
        joints_passed,
        intrinsic_passed: intrinsic.section.passed(),
    })
}

/// Adds `from`'s metrics under the same subjects, each name prefixed.
fn merge_prefixed(
    into: &mut BTreeMap<String, BTreeMap<String, f64>>,
    from: &BTreeMap<String, BTreeMap<String, f64>>,
    prefix: &str,
) {
    for (subject, values) in from {
        let entry = into.entry(subject.clone()).or_default();
        for (name, value) in values {
            entry.insert(format!("{prefix}{name}"), *value);
        }
    }
}
