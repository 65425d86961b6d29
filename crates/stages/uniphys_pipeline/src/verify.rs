//! The verify stage: intrinsic checks (levels 0-4) and articulation sweeps with feedback
//! correction, on the grounded record.

use std::collections::BTreeMap;

use uniphys_geometry::TriMesh;
use uniphys_types::{AssetRecord, CheckOutcome, ReportSection};
use uniphys_verify::{Scene, SweepParams, verify_articulation, verify_intrinsic};

use crate::PipelineResult;

/// Parameters of the verify stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerifyOptions {
    /// Sweep parameters (steps, thresholds relative to the object).
    pub sweep: SweepParams,
    /// Surface samples per part for contact measurement.
    pub samples_per_part: usize,
    /// Try to correct joints that fail their sweep.
    pub correct: bool,
}

impl Default for VerifyOptions {
    /// The default sweep (200 steps), 1500 samples per part, correction on.
    fn default() -> Self {
        Self {
            sweep: SweepParams::default(),
            samples_per_part: 1500,
            correct: true,
        }
    }
}

/// What verification produced.
#[derive(Debug, Clone)]
pub(crate) struct Verified {
    /// The record with corrected joints.
    pub(crate) record: AssetRecord,
    /// Sections `intrinsic` and `articulation`.
    pub(crate) sections: Vec<ReportSection>,
    /// Numbers behind the checks, by subject.
    pub(crate) metrics: BTreeMap<String, BTreeMap<String, f64>>,
    /// One line per corrected joint.
    pub(crate) corrections: Vec<String>,
    pub(crate) joints_swept: usize,
    pub(crate) joints_passed: usize,
    pub(crate) intrinsic_passed: bool,
}

/// Runs intrinsic and articulation verification; failed joints are corrected when a variant
/// passes (the record then carries the corrected joint).
pub(crate) fn verify(
    mut record: AssetRecord,
    meshes: &[TriMesh],
    colliders: &[Vec<TriMesh>],
    options: &VerifyOptions,
) -> PipelineResult<Verified> {
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
    let mut metrics = articulation.metrics.clone();
    metrics.insert("object".to_owned(), intrinsic.metrics.clone());
    Ok(Verified {
        record,
        intrinsic_passed: intrinsic.section.passed(),
        sections: vec![intrinsic.section, articulation.section],
        metrics,
        corrections: articulation.corrections,
        joints_swept,
        joints_passed,
    })
}
