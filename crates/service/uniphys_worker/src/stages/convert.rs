//! `convert`: the whole in-process pipeline (ingest → prepare → colliders → ground → verify →
//! export) on the submitted file; writes every exported file (URDF, MJCF, meshes, record,
//! report) as artifacts. An asset that fails verification is still written, with `passed: false`
//! in the summary, exactly as `uniphys run` does. When the job has a `decompose` stage that split
//! the input, its face-to-part map gives the parts.

use std::time::Duration;

use serde_json::Value;
use uniphys_pipeline::{PipelineError, Progress, RunOptions, Stage as PipelineStage, run};
use uniphys_types::{ConvertSummary, DatasetFacts, ServiceStage};

use crate::outputs::{OutputWriter, summary_value};
use crate::source::SourceFile;
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::decompose::FACE_PARTS_FILE;

/// The convert stage.
#[derive(Clone, Debug, Default)]
pub struct ConvertStage {
    /// Pipeline options.
    pub options: RunOptions,
}

/// Maps the pipeline's progress onto the run's: each of its six stages is a sixth.
struct Relay<'a>(&'a StageControl);

fn position(stage: PipelineStage) -> f64 {
    let index = PipelineStage::ALL
        .iter()
        .position(|s| *s == stage)
        .unwrap_or(0);
    index as f64 / PipelineStage::ALL.len() as f64
}

impl Progress for Relay<'_> {
    fn stage_started(&self, stage: PipelineStage) {
        self.0.progress(position(stage), stage.name());
    }

    fn stage_advanced(&self, stage: PipelineStage, done: usize, total: usize) {
        let within = done as f64 / total.max(1) as f64;
        let share = 1.0 / PipelineStage::ALL.len() as f64;
        self.0.progress(
            position(stage) + within * share,
            format!("{} {done}/{total}", stage.name()),
        );
    }

    fn stage_finished(&self, _: PipelineStage, _: Duration, _: &str) {}
}

impl Stage for ConvertStage {
    fn name(&self) -> &str {
        ServiceStage::Convert.name()
    }

    fn version(&self) -> u32 {
        // 2: the parts come from an upstream `decompose` when it split the input.
        2
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        input.upstream(ServiceStage::Ingest.name())?;
        let source = SourceFile::fetch(input)?;
        let mut options = self.options.clone();
        if let Some(face_parts) = stored_face_parts(input)? {
            options.face_parts = Some(face_parts);
        }
        let output =
            run(source.path(), &options, &Relay(control)).map_err(|e| classify(&e, &source))?;
        control.check()?;
        let files = output.artifacts.len();
        for artifact in output.artifacts {
            let bytes = source.without_local_paths_in(&artifact.path, artifact.bytes);
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

/// A failure the same run may get past later ([`PipelineError::is_transient`]) is retried.
fn classify(error: &PipelineError, source: &SourceFile) -> StageError {
    let message = source.without_local_paths(&format!("the pipeline failed: {error}"));
    if error.is_transient() {
        StageError::Transient(message)
    } else {
        StageError::Permanent(message)
    }
}

/// The face-to-part map written by an upstream `decompose` stage, if the job has one and it
/// split the input.
fn stored_face_parts(input: &StageInput) -> Result<Option<Vec<u32>>, StageError> {
    let Some((_, manifest)) = input
        .upstream
        .iter()
        .find(|(name, _)| name == ServiceStage::Decompose.name())
    else {
        return Ok(None);
    };
    let Some(entry) = manifest.artifact(FACE_PARTS_FILE) else {
        return Ok(None);
    };
    let bytes = input.fetch(&entry.key)?;
    serde_json::from_slice(&bytes)
        .map(Some)
        .map_err(|e| StageError::Permanent(format!("{}: {e}", entry.key)))
}
