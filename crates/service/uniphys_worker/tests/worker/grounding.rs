//! The pipeline's stages as stages: `infer` alone calls the UniPhysGen server and stores its
//! answers, `ground` alone calls the LVLM and stores what the grounders decided, `verify` stores
//! what it checked and corrected; a `ground`, `verify` or `convert` that fails is retried alone
//! and asks the model server nothing. The models are the rule-based UniPhysGen test server and
//! an LVLM replay server answering with recorded answers, both on loopback, counting the
//! requests they get.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use serde_json::Value;
use uniphys_pipeline::{LearnedOptions, ModelAnswers, RunOptions};
use uniphys_queue::{JobDetail, JobState, OutputManifest};
use uniphys_types::{
    AssetRecord, GroundSummary, GroundedAsset, InferSummary, ServiceStage, VerifiedAsset,
    VerifySummary,
};
use uniphys_uniphysgen::test_server::TestServer;
use uniphys_uniphysgen::{ClientConfig, PointOptions};
use uniphys_worker::stages::{
    ConvertStage, DecomposeStage, GROUNDED_FILE, GroundStage, INFERRED_FILE, VERIFIED_FILE,
    VerifyStage,
};
use uniphys_worker::{OutputWriter, Stage, StageControl, StageError, StageInput, StageRegistry};

use crate::fixture;

/// `stage`, failing transiently at the end of its first run (its work done, as a worker lost
/// just before reporting it).
struct FailsOnce<S> {
    stage: S,
    failed: AtomicBool,
}

impl<S: Stage> Stage for FailsOnce<S> {
    fn name(&self) -> &str {
        self.stage.name()
    }

    fn version(&self) -> u32 {
        self.stage.version()
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        let summary = self.stage.run(input, out, control)?;
        if !self.failed.swap(true, Ordering::SeqCst) {
            return Err(StageError::Transient("a worker lost mid-stage".into()));
        }
        Ok(summary)
    }
}

/// Every stage of `job` ran once, but the `retried` ones, which ran twice.
fn assert_retried_alone(job: &JobDetail, retried: &[ServiceStage]) {
    for stage in ServiceStage::ALL {
        let run = job.stage(stage.name()).expect("every stage ran");
        let attempts = if retried.contains(&stage) { 2 } else { 1 };
        assert_eq!(run.attempt, attempts, "{}", stage.name());
    }
}

/// The manifest of `job`'s run of `stage` and its summary.
fn stage_output<T: serde::de::DeserializeOwned>(
    job: &JobDetail,
    stage: ServiceStage,
) -> (OutputManifest, T) {
    let run = job.stage(stage.name()).expect("the stage ran");
    let manifest =
        OutputManifest::from_value(run.output_manifest.as_ref().expect("manifest")).expect("shape");
    let summary = serde_json::from_value(manifest.summary.clone()).expect("the stage's summary");
    (manifest, summary)
}

/// The JSON file `file` of `manifest`, read from the fixture's artifact store.
async fn stored<T: serde::de::DeserializeOwned>(
    f: &crate::Fixture,
    manifest: &OutputManifest,
    file: &str,
) -> T {
    let entry = manifest.artifact(file).expect("the file is stored");
    serde_json::from_slice(&f.artifacts.get(&entry.key).await.expect("stored bytes"))
        .expect("the file's type")
}

fn fails_once<S: Stage>(stage: S) -> FailsOnce<S> {
    FailsOnce {
        stage,
        failed: AtomicBool::new(false),
    }
}

/// The real pipeline grounding with the UniPhysGen server at `url`.
fn convert_with_model(url: String) -> ConvertStage {
    ConvertStage {
        options: RunOptions {
            learned: Some(LearnedOptions {
                client: ClientConfig {
                    base_url: url,
                    ..ClientConfig::default()
                },
                points: PointOptions {
                    object_points: 20_000,
                    min_part_points: 2_000,
                    seed: 42,
                },
                ..LearnedOptions::default()
            }),
            ..RunOptions::default()
        },
    }
}

fn mug() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../test_data/examples/mug.glb")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn stages_after_infer_retried_after_failures_ask_the_model_nothing() {
    let server = TestServer::start().expect("test server");
    let f = fixture().await;
    let convert = convert_with_model(server.url());
    let registry = StageRegistry::pipeline_with(DecomposeStage::default(), convert.clone())
        .with(fails_once(GroundStage {
            options: convert.options.clone(),
        }))
        .with(fails_once(VerifyStage {
            options: convert.options.clone(),
        }))
        .with(fails_once(convert));
    let job = f
        .run_pipeline_with(&mug(), registry, Duration::from_secs(600))
        .await;
    assert_eq!(job.state, JobState::Succeeded, "{:?}", job.stages);
    assert_retried_alone(
        &job,
        &[
            ServiceStage::Ground,
            ServiceStage::Verify,
            ServiceStage::Convert,
        ],
    );
    // `infer` stored the model's answers for every part.
    let (manifest, summary): (_, InferSummary) = stage_output(&job, ServiceStage::Infer);
    assert!(summary.model.is_some(), "{summary:?}");
    let answers: ModelAnswers = stored(&f, &manifest, INFERRED_FILE).await;
    assert_eq!(answers.physics.parts.len(), summary.parts);
    // Only `infer` asked the model: one request per task, none from either attempt of `ground`,
    // `verify` or `convert`; `ground` applied the stored answers.
    let (manifest, summary): (_, GroundSummary) = stage_output(&job, ServiceStage::Ground);
    assert!(
        summary
            .grounded_by
            .iter()
            .any(|p| p.starts_with("uniphysgen")),
        "{summary:?}"
    );
    let grounded: GroundedAsset = stored(&f, &manifest, GROUNDED_FILE).await;
    assert_eq!(grounded.record.parts.len(), summary.parts);
    let alone = predict_requests_of_one_grounding(&server).await;
    assert_eq!(
        server.predict_requests(),
        2 * alone,
        "the job asked as much as one grounding (measured again after it)"
    );
    // `verify` stored what it checked, and the exported record is that verification's record:
    // the model's values are in it.
    let (manifest, summary): (_, VerifySummary) = stage_output(&job, ServiceStage::Verify);
    let verified: VerifiedAsset = stored(&f, &manifest, VERIFIED_FILE).await;
    assert_eq!(summary.joints_swept, verified.joints_swept);
    assert!(summary.joints_swept > 0, "{summary:?}");
    assert_eq!(
        verified.record.object.category.value,
        grounded.record.object.category.value
    );
    let (manifest, _): (_, Value) = stage_output(&job, ServiceStage::Convert);
    let record: AssetRecord = stored(&f, &manifest, "record.json").await;
    assert_eq!(record, verified.record);
}

/// Grounds the mug once in process with the model at `server`, returning the requests it took.
async fn predict_requests_of_one_grounding(server: &TestServer) -> usize {
    let before = server.predict_requests();
    let options = convert_with_model(server.url()).options;
    tokio::task::spawn_blocking(move || {
        uniphys_pipeline::ground_asset(&mug(), &options, &uniphys_pipeline::NoProgress)
            .expect("grounding")
    })
    .await
    .expect("grounding thread");
    server.predict_requests() - before
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_ground_stage_that_fails_transiently_is_retried_alone() {
    let f = fixture().await;
    let convert = ConvertStage::default();
    let registry = StageRegistry::pipeline_with(DecomposeStage::default(), convert.clone()).with(
        fails_once(GroundStage {
            options: convert.options,
        }),
    );
    let job = f
        .run_pipeline_with(&mug(), registry, Duration::from_secs(600))
        .await;
    assert_eq!(job.state, JobState::Succeeded, "{:?}", job.stages);
    assert_retried_alone(&job, &[ServiceStage::Ground]);
    let ground = job.stage("ground").expect("ground");
    assert!(
        ground.errors[0].message.contains("a worker lost mid-stage"),
        "{:?}",
        ground.errors
    );
}

/// A chat completion carrying `answer` as the LVLM contract's JSON block.
fn completion(answer: &Value) -> Value {
    let text = format!("===BEGIN_JSON===\n{answer:#}\n===END_JSON===");
    serde_json::json!({
        "id": "chatcmpl-worker", "object": "chat.completion", "model": "recorded-model",
        "choices": [{"index": 0, "finish_reason": "stop",
                     "message": {"role": "assistant", "content": text}}],
        "usage": {"prompt_tokens": 2000, "completion_tokens": 300, "total_tokens": 2300}
    })
}

/// A recorded answer of the annotate crate's fixtures.
fn recorded(name: &str) -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../stages/uniphys_annotate/tests/fixtures")
        .join(name);
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).expect("json")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn ground_and_convert_each_lost_once_ask_the_lvlm_once() {
    use uniphys_replay::{RecordedRequest, ReplayServer, Reply};
    let server = ReplayServer::start_with(std::sync::Arc::new(|request: &RecordedRequest| {
        let answer = if request.body_text().contains("UniPhys properties prompt") {
            recorded("box_with_lid_properties.json")
        } else {
            recorded("box_with_lid_articulation.json")
        };
        Reply::json(200, completion(&answer))
    }))
    .expect("replay server");
    let f = fixture().await;
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("box_with_lid.glb");
    let asset = uniphys_examples::example("box_with_lid")
        .expect("example")
        .asset;
    let glb = uniphys_examples::write_glb(&asset, uniphys_examples::GlbFrame::YUp).expect("glb");
    std::fs::write(&path, glb).expect("write");
    let convert = ConvertStage {
        options: RunOptions {
            lvlm: Some(uniphys_pipeline::LvlmOptions {
                client: uniphys_lvlm::LvlmConfig {
                    base_url: format!("{}/v1", server.url()),
                    model: "recorded-model".into(),
                    max_concurrency: 2,
                    ..uniphys_lvlm::LvlmConfig::default()
                },
                budget_usd: Some(1.0),
                cache_dir: Some(dir.path().join("lvlm-answers")),
                annotate: uniphys_annotate::AnnotateOptions {
                    panel_px: 96,
                    points_per_part: 400,
                    ..uniphys_annotate::AnnotateOptions::default()
                },
                ..uniphys_pipeline::LvlmOptions::default()
            }),
            ..RunOptions::default()
        },
    };
    let registry = StageRegistry::pipeline_with(DecomposeStage::default(), convert.clone())
        .with(fails_once(GroundStage {
            options: convert.options.clone(),
        }))
        .with(fails_once(convert));
    let job = f
        .run_pipeline_with(&path, registry, Duration::from_secs(600))
        .await;
    assert_eq!(job.state, JobState::Succeeded, "{:?}", job.stages);
    assert_retried_alone(&job, &[ServiceStage::Ground, ServiceStage::Convert]);
    // One properties and one articulation request, from `ground`'s first attempt: its retry
    // reads the answers from the cache and writes the same grounding; `verify` and `convert`
    // ask nothing.
    assert_eq!(server.requests().len(), 2, "{:?}", server.requests().len());
    let (_, summary): (_, GroundSummary) = stage_output(&job, ServiceStage::Ground);
    assert!(
        summary.grounded_by.iter().any(|p| p.starts_with("lvlm:")),
        "{summary:?}"
    );
}
