//! `convert`: export of the verification an upstream `verify` stage stored of the grounding an
//! upstream `ground` stage stored, on the asset `ingest` stored; writes every exported file (URDF,
//! MJCF, meshes, record, report) as artifacts. A job submitted before those stages existed has
//! neither (or only the grounding): the missing stages run here in process, as `uniphys run` runs
//! them. An asset that fails verification is still written, with `passed: false` in the summary,
//! exactly as `uniphys run` does. When the job has a `decompose` stage that split the input, its
//! face-to-part map gives the parts. With a stored grounding no UniPhysGen server or LVLM is asked,
//! and with a stored verification nothing is verified again: a retry of this stage repeats neither.

use serde_json::Value;
use uniphys_pipeline::{RunOptions, Stage as PipelineStage, run};
use uniphys_types::{ConvertSummary, DatasetFacts, ServiceStage};

use crate::outputs::{OutputWriter, summary_value};
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::relay::Relay;
use crate::stages::upstream::{pipeline_start, stored_grounding, stored_verification};

/// The pipeline stages a `convert` run goes through after a `verify` stage.
const AFTER_VERIFY: [PipelineStage; 2] = [PipelineStage::Ingest, PipelineStage::Export];
/// ... after a `ground` stage only (a job submitted before `verify` existed).
const AFTER_GROUND: [PipelineStage; 3] = [
    PipelineStage::Ingest,
    PipelineStage::Verify,
    PipelineStage::Export,
];

/// The convert stage.
#[derive(Clone, Debug, Default)]
pub struct ConvertStage {
    /// Pipeline options.
    pub options: RunOptions,
}

impl Stage for ConvertStage {
    fn name(&self) -> &str {
        ServiceStage::Convert.name()
    }

    fn version(&self) -> u32 {
        // 2: the parts come from an upstream `decompose` when it split the input.
        // 3: the grounding comes from an upstream `ground` when the job has one.
        // 4: the verification comes from an upstream `verify` when the job has one.
        // 5: the asset comes from `ingest`'s stored copy when it wrote one.
        5
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        let (asset, mut options) = pipeline_start(input, &self.options)?;
        options.grounded = stored_grounding(input)?;
        if options.grounded.is_some() {
            options.verified = stored_verification(input)?;
        }
        let stages: &[PipelineStage] = match (&options.grounded, &options.verified) {
            (Some(_), Some(_)) => &AFTER_VERIFY,
            (Some(_), None) => &AFTER_GROUND,
            (None, _) => &PipelineStage::ALL,
        };
        let output = run(asset.source(), &options, &Relay::new(control, stages))
            .map_err(|e| asset.failed(&e))?;
        control.check()?;
        let files = output.artifacts.len();
        for artifact in output.artifacts {
            let bytes = asset.without_local_paths_in(&artifact.path, artifact.bytes);
            out.put(&artifact.path, bytes)?;
        }
        let summary = ConvertSummary {
            passed: output.report.passed(),
            name: output.record.name.clone(),
            parts: output.record.parts.len(),
            joints: output.record.joints.len(),
            files,
            stage_secs: output
                .timings
                .iter()
                .map(|(stage, elapsed)| (stage.name().to_owned(), elapsed.as_secs_f64()))
                .collect(),
            dataset: Some(DatasetFacts::of(&output.record)),
        };
        summary_value(&summary)
    }
}
