//! The source is parsed once: `ingest` stores what it read, and every later stage reads that.
//! A job whose submitted file is deleted from the store right after `ingest` still goes through
//! every stage and exports the same files as a job that kept it.

use std::time::Duration;

use serde_json::Value;
use uniphys_pipeline::IngestedAsset;
use uniphys_queue::{JobDetail, JobState, OutputManifest};
use uniphys_types::ServiceStage;
use uniphys_worker::stages::{ConvertStage, DecomposeStage, INGESTED_FILE, IngestStage};
use uniphys_worker::{OutputWriter, Stage, StageControl, StageError, StageInput, StageRegistry};

use crate::{Fixture, fixture};

/// `ingest`, then the submitted file deleted from the artifact store: a later stage that
/// fetched it would fail.
struct IngestThenDropSource(IngestStage);

impl Stage for IngestThenDropSource {
    fn name(&self) -> &str {
        self.0.name()
    }

    fn version(&self) -> u32 {
        self.0.version()
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        let summary = self.0.run(input, out, control)?;
        input
            .runtime
            .block_on(input.artifacts.delete(&input.asset.source_uri))
            .map_err(|e| StageError::Permanent(format!("deleting the source: {e}")))?;
        Ok(summary)
    }
}

fn registry() -> StageRegistry {
    StageRegistry::pipeline_with(DecomposeStage::default(), ConvertStage::default())
}

/// The manifest of `job`'s run of `stage`.
fn manifest(job: &JobDetail, stage: ServiceStage) -> OutputManifest {
    let run = job.stage(stage.name()).expect("the stage ran");
    OutputManifest::from_value(run.output_manifest.as_ref().expect("manifest")).expect("shape")
}

/// The bytes of `file` in the output of `job`'s stage `stage`.
async fn output(f: &Fixture, job: &JobDetail, stage: ServiceStage, file: &str) -> Vec<u8> {
    let manifest = manifest(job, stage);
    let entry = manifest
        .artifact(file)
        .unwrap_or_else(|| panic!("{file} of {stage} is stored"));
    f.artifacts.get(&entry.key).await.expect("stored bytes")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn stages_after_ingest_never_read_the_submitted_file() {
    // A real object sent as an archive: a PartNet-Mobility dishwasher (a door on a hinge).
    let folder = uniphys_examples::shared_partnet_object("kitchen-11622");
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("kitchen-11622.tar.gz");
    uniphys_archive::pack_folder(&folder, &path).expect("pack");
    let kept = fixture().await;
    let with_source = kept
        .run_pipeline_with(&path, registry(), Duration::from_secs(600))
        .await;
    assert_eq!(
        with_source.state,
        JobState::Succeeded,
        "{:?}",
        with_source.stages
    );
    let dropped = fixture().await;
    let ingest = IngestThenDropSource(IngestStage {
        options: ConvertStage::default().options.ingest,
    });
    let without_source = dropped
        .run_pipeline_with(&path, registry().with(ingest), Duration::from_secs(600))
        .await;
    assert_eq!(
        without_source.state,
        JobState::Succeeded,
        "{:?}",
        without_source.stages
    );
    for stage in ServiceStage::ALL {
        let run = without_source.stage(stage.name()).expect("every stage ran");
        assert_eq!(run.attempt, 1, "{stage} ran once");
    }
    let stored = output(
        &dropped,
        &without_source,
        ServiceStage::Ingest,
        INGESTED_FILE,
    )
    .await;
    let stored = IngestedAsset::from_bytes(&stored).expect("a stored asset");
    assert_eq!(stored.loaded.source.file_name, "mobility.urdf");
    assert_eq!(stored.loaded.asset.joints.len(), 1);
    // Every exported file is the same, byte for byte.
    let files = |job: &JobDetail| -> Vec<(String, String)> {
        manifest(job, ServiceStage::Convert)
            .artifacts
            .into_iter()
            .map(|a| (a.name, a.sha256))
            .collect()
    };
    assert_eq!(files(&with_source), files(&without_source));
}
