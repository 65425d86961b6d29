//! The worker against a real store (SQLite in a temp dir) and a local object store: stand-in
//! graphs run to the end with deterministic outputs, a broken input dead-letters at once with a
//! readable error, the real pipeline converts an example (and decomposes one given in one piece),
//! shutdown releases what it holds, and a cancel stops a running stage and removes what it wrote;
//! the pipeline's stages retried alone, a retried `convert` asking no model again (`grounding`).

mod grounding;
mod stored_asset;

use std::path::Path;
use std::time::{Duration, Instant};

use tokio_util::sync::CancellationToken;
use uniphys_geometry::{MeshAsset, MeshPart};
use uniphys_hints::Hints;
use uniphys_queue::{
    JobSpec, JobState, NewAsset, OutputManifest, QueueStore, StageState, StoreConfig, TenantId,
};
use uniphys_storage::ArtifactStore;
use uniphys_telemetry::Metrics;
use uniphys_types::{ConvertSummary, DecomposeStageSummary, IngestSummary};
use uniphys_worker::{
    OutputWriter, Stage, StageControl, StageError, StageInput, StageRegistry, StageSlots, Worker,
    WorkerConfig, pipeline_job_spec,
};

struct Fixture {
    _dir: tempfile::TempDir,
    store: QueueStore,
    artifacts: ArtifactStore,
    tenant: TenantId,
}

async fn fixture() -> Fixture {
    let dir = tempfile::tempdir().expect("temp dir");
    let url = format!("sqlite:{}", dir.path().join("queue.db").display());
    let store = QueueStore::open(&StoreConfig::new(url)).expect("store");
    store.migrate().await.expect("migrate");
    let tenant = store.create_tenant("acme").await.expect("tenant");
    let artifacts = ArtifactStore::local(&dir.path().join("objects")).expect("objects");
    Fixture {
        _dir: dir,
        store,
        artifacts,
        tenant,
    }
}

/// One slot for each stage of the pipeline.
/// One slot for every stage of the pipeline.
fn pipeline_slots() -> Vec<(&'static str, usize)> {
    uniphys_types::ServiceStage::ALL
        .iter()
        .map(|stage| (stage.name(), 1))
        .collect()
}

fn config(stages: &[(&str, usize)]) -> WorkerConfig {
    WorkerConfig {
        stages: stages
            .iter()
            .map(|(name, n)| StageSlots::new(*name, *n))
            .collect(),
        lease: Duration::from_secs(5),
        poll_interval: Duration::from_millis(200),
        reap_interval: Duration::from_millis(500),
        shutdown_grace: Duration::from_millis(300),
    }
}

impl Fixture {
    async fn submit_file(&self, path: &Path, spec: &JobSpec) -> uniphys_queue::Submission {
        let bytes = std::fs::read(path).expect("example file");
        let name = path.file_name().expect("name").to_string_lossy();
        let digest = format!("{:x}", bytes.len()) + &name;
        let key = format!("sources/t{}/{digest}/{name}", self.tenant.0);
        let size = bytes.len() as u64;
        self.artifacts.put(&key, bytes).await.expect("put source");
        let asset = NewAsset {
            content_digest: format!("sha256:{digest}"),
            source_uri: key,
            size_bytes: size,
        };
        self.store
            .submit(self.tenant, &asset, spec)
            .await
            .expect("submit")
    }

    /// Submits a one-stage job of the stand-in stage `slow` for content named `name` (no
    /// source object: the stand-in does not read it).
    async fn submit_slow(&self, name: &str) -> uniphys_queue::Submission {
        let asset = NewAsset {
            content_digest: format!("sha256:{name}"),
            source_uri: format!("sources/{name}"),
            size_bytes: 1,
        };
        self.store
            .submit(self.tenant, &asset, &JobSpec::chain(&["slow"]))
            .await
            .expect("submit")
    }

    fn start(
        &self,
        registry: StageRegistry,
        config: WorkerConfig,
    ) -> (CancellationToken, tokio::task::JoinHandle<()>) {
        let worker = Worker::new(
            self.store.clone(),
            self.artifacts.clone(),
            Hints::local(),
            Metrics::new(),
            registry,
            config,
        )
        .expect("valid worker");
        let shutdown = CancellationToken::new();
        let token = shutdown.clone();
        let handle = tokio::spawn(async move {
            worker.run(token).await.expect("worker runs");
        });
        (shutdown, handle)
    }

    /// Submits `path` with the pipeline's graph, runs the real pipeline on one slot per stage
    /// until the job finishes (or `within` passes), stops the worker and returns the job.
    async fn run_pipeline(&self, path: &Path, within: Duration) -> uniphys_queue::JobDetail {
        self.run_pipeline_with(path, StageRegistry::pipeline(), within)
            .await
    }

    /// [`Self::run_pipeline`] with the stages of `registry`.
    async fn run_pipeline_with(
        &self,
        path: &Path,
        registry: StageRegistry,
        within: Duration,
    ) -> uniphys_queue::JobDetail {
        let sub = self.submit_file(path, &pipeline_job_spec()).await;
        let (shutdown, handle) = self.start(registry, config(&pipeline_slots()));
        self.wait_finished(&[sub.job_id], within).await;
        shutdown.cancel();
        handle.await.expect("worker stops");
        self.store
            .get_job(self.tenant, sub.job_id)
            .await
            .expect("job")
    }

    async fn wait_finished(&self, jobs: &[uniphys_queue::JobId], within: Duration) {
        let until = Instant::now() + within;
        loop {
            let mut open = 0;
            for job in jobs {
                let detail = self.store.get_job(self.tenant, *job).await.expect("job");
                if detail.state == JobState::Running {
                    open += 1;
                }
            }
            if open == 0 {
                return;
            }
            assert!(
                Instant::now() < until,
                "{open} jobs still running after {within:?}"
            );
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn stand_in_graphs_complete_with_deterministic_outputs() {
    let f = fixture().await;
    let spec = JobSpec::chain(&["a", "b"]);
    let mut jobs = Vec::new();
    for i in 0..20 {
        let asset = NewAsset {
            content_digest: format!("sha256:{i}"),
            source_uri: format!("sources/{i}"),
            size_bytes: 1,
        };
        jobs.push(
            f.store
                .submit(f.tenant, &asset, &spec)
                .await
                .expect("submit")
                .job_id,
        );
    }
    let registry = StageRegistry::stand_ins(&["a", "b"], Duration::from_millis(5));
    let (shutdown, handle) = f.start(registry, config(&[("a", 3), ("b", 2)]));
    f.wait_finished(&jobs, Duration::from_secs(60)).await;
    shutdown.cancel();
    handle.await.expect("worker stops");

    for job in &jobs {
        let detail = f.store.get_job(f.tenant, *job).await.expect("job");
        assert_eq!(detail.state, JobState::Succeeded);
        let a = detail.stage("a").expect("a");
        let b = detail.stage("b").expect("b");
        assert_eq!(a.attempt, 1, "one execution each without faults");
        let ma = OutputManifest::from_value(a.output_manifest.as_ref().expect("manifest"))
            .expect("shape");
        let mb = OutputManifest::from_value(b.output_manifest.as_ref().expect("manifest"))
            .expect("shape");
        let out_a = f
            .artifacts
            .get(&ma.artifacts[0].key)
            .await
            .expect("a's output");
        let out_b = f
            .artifacts
            .get(&mb.artifacts[0].key)
            .await
            .expect("b's output");
        assert!(out_a.starts_with(b"a:"));
        assert!(out_b.starts_with(b"b:"));
        assert_ne!(out_a, out_b);
        // b's key and bytes depend on a's output: its prefix carries a's digest.
        assert!(
            mb.artifacts[0]
                .key
                .starts_with(&format!("{}/b/v1/", detail.asset_id.0))
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_broken_input_is_dead_lettered_at_once_with_a_readable_error() {
    let f = fixture().await;
    let dir = tempfile::tempdir().expect("temp dir");
    let broken = dir.path().join("broken.glb");
    std::fs::write(&broken, b"glTF this is not a real binary glTF").expect("write");
    let job = f.run_pipeline(&broken, Duration::from_secs(60)).await;
    assert_eq!(job.state, JobState::Dead);
    let ingest = job.stage("ingest").expect("ingest");
    assert_eq!(ingest.state, StageState::Dead);
    assert_eq!(ingest.attempt, 1, "a permanent failure is not retried");
    let message = &ingest.errors[0].message;
    assert!(message.contains("the input cannot be read"), "{message}");
    assert!(message.contains("broken.glb"), "{message}");
    // The worker's temporary copy is its own business.
    let temp = std::env::temp_dir().display().to_string();
    assert!(!message.contains(&temp), "{message}");
    // Downstream waits, so a retry of the dead job can resume it.
    assert_eq!(
        job.stage("convert").expect("convert").state,
        StageState::Blocked
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn the_pipeline_converts_an_example_into_its_artifacts() {
    let f = fixture().await;
    let mug = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../test_data/examples/mug.glb");
    let job = f.run_pipeline(&mug, Duration::from_secs(600)).await;
    assert_eq!(job.state, JobState::Succeeded, "{:?}", job.stages);
    let convert = job.stage("convert").expect("convert");
    let manifest = OutputManifest::from_value(convert.output_manifest.as_ref().expect("manifest"))
        .expect("shape");
    for name in ["model.urdf", "model.xml", "record.json", "report.json"] {
        let entry = manifest
            .artifact(name)
            .unwrap_or_else(|| panic!("{name} in {manifest:?}"));
        let bytes = f.artifacts.get(&entry.key).await.expect("artifact");
        assert_eq!(bytes.len() as u64, entry.bytes);
    }
    assert!(
        manifest.summary["parts"].as_u64().is_some_and(|n| n >= 1),
        "{}",
        manifest.summary
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_real_urdf_folder_sent_as_an_archive_is_converted_with_its_joints() {
    let f = fixture().await;
    // A table of the shared set: a URDF, a drawer on a slide, texture images its MTLs name
    // but the folder lacks.
    let folder = uniphys_examples::shared_partnet_object("gensim2-20453");
    let dir = tempfile::tempdir().expect("temp dir");
    let archive = dir.path().join("gensim2-20453.tar.gz");
    uniphys_archive::pack_folder(&folder, &archive).expect("pack");
    let job = f.run_pipeline(&archive, Duration::from_secs(600)).await;
    assert_eq!(job.state, JobState::Succeeded, "{:?}", job.stages);
    let convert = job.stage("convert").expect("convert");
    let manifest = OutputManifest::from_value(convert.output_manifest.as_ref().expect("manifest"))
        .expect("shape");
    let record = manifest.artifact("record.json").expect("record");
    let record: serde_json::Value =
        serde_json::from_slice(&f.artifacts.get(&record.key).await.expect("record")).expect("json");
    let kinds: Vec<&str> = record["joints"]
        .as_array()
        .expect("joints")
        .iter()
        .filter_map(|j| j["kind"].as_str())
        .collect();
    assert_eq!(kinds, ["prismatic"], "{}", record["joints"]);
    assert_eq!(record["source"]["file_name"], "mobility.urdf");
    // The ingest run's manifest stays small: the warnings' count and the first few.
    let ingest = job.stage("ingest").expect("ingest");
    let summary: IngestSummary = serde_json::from_value(
        OutputManifest::from_value(ingest.output_manifest.as_ref().expect("manifest"))
            .expect("shape")
            .summary,
    )
    .expect("an ingest summary");
    assert!(summary.warning_count.is_some_and(|n| n > 5), "{summary:?}");
    assert_eq!(summary.warnings.len(), 5);
    // Nothing written names the worker's temporary folder: a retry elsewhere writes the same.
    let temp = std::env::temp_dir().display().to_string();
    for name in ["report.json", "record.json"] {
        let entry = manifest.artifact(name).expect(name);
        let text = String::from_utf8(f.artifacts.get(&entry.key).await.expect(name)).expect("text");
        assert!(!text.contains(&temp), "{name} names {temp}");
        if name == "report.json" {
            assert!(
                text.contains("asset/textured_objs/") && text.contains("does not exist"),
                "the missing textures are named by their place in the asset"
            );
        }
    }
}

/// A stage whose summary is far over the queue's manifest limit (a stage bug).
struct Chatty;

impl Stage for Chatty {
    fn name(&self) -> &str {
        "chatty"
    }

    fn version(&self) -> u32 {
        1
    }

    fn run(
        &self,
        _input: &StageInput,
        _out: &mut OutputWriter,
        _control: &StageControl,
    ) -> Result<serde_json::Value, StageError> {
        Ok(serde_json::json!({ "lines": vec!["a warning of some length"; 10_000] }))
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_manifest_over_the_queues_limit_fails_the_run_at_once_saying_why() {
    let f = fixture().await;
    let asset = NewAsset {
        content_digest: "sha256:chatty".into(),
        source_uri: "sources/chatty".into(),
        size_bytes: 1,
    };
    let sub = f
        .store
        .submit(f.tenant, &asset, &JobSpec::chain(&["chatty"]))
        .await
        .expect("submit");
    let (shutdown, handle) = f.start(
        StageRegistry::stand_ins(&[], Duration::ZERO).with(Chatty),
        config(&[("chatty", 1)]),
    );
    f.wait_finished(&[sub.job_id], Duration::from_secs(60))
        .await;
    shutdown.cancel();
    handle.await.expect("worker stops");
    let job = f.store.get_job(f.tenant, sub.job_id).await.expect("job");
    let run = job.stage("chatty").expect("stage");
    assert_eq!(run.state, StageState::Dead);
    assert_eq!(run.attempt, 1, "not left to lease recovery, not retried");
    assert!(
        run.errors[0].message.contains("output manifest"),
        "{}",
        run.errors[0].message
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn an_asset_in_one_piece_is_decomposed_and_converted_with_the_found_parts() {
    let f = fixture().await;
    let example = uniphys_examples::example("box_with_lid").expect("example");
    let one_piece = MeshAsset {
        parts: vec![MeshPart {
            name: "scan".into(),
            mesh: example.asset.merged(),
        }],
        joints: Vec::new(),
        ..example.asset.clone()
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("box_in_one_piece.glb");
    let glb =
        uniphys_examples::write_glb(&one_piece, uniphys_examples::GlbFrame::YUp).expect("glb");
    std::fs::write(&path, glb).expect("write");
    let job = f.run_pipeline(&path, Duration::from_secs(600)).await;
    assert_eq!(job.state, JobState::Succeeded, "{:?}", job.stages);
    let manifest = |stage: &str| {
        let run = job.stage(stage).expect("stage");
        OutputManifest::from_value(run.output_manifest.as_ref().expect("manifest")).expect("shape")
    };
    let decompose = manifest("decompose");
    let summary: DecomposeStageSummary =
        serde_json::from_value(decompose.summary.clone()).expect("a decompose summary");
    assert!(summary.decomposed, "{summary:?}");
    assert_eq!(summary.input_parts, Some(1), "{summary:?}");
    // The box and its lid, no more and no fewer.
    let found = summary.parts as u64;
    assert_eq!(found, example.asset.parts.len() as u64, "{summary:?}");
    let entry = decompose.artifact("face_parts.json").expect("face map");
    let face_parts: Vec<u32> =
        serde_json::from_slice(&f.artifacts.get(&entry.key).await.expect("map")).expect("json");
    assert_eq!(face_parts.len(), example.asset.merged().triangle_count());
    // convert built the asset from the found parts, not from the one piece submitted.
    let convert: ConvertSummary =
        serde_json::from_value(manifest("convert").summary).expect("a convert summary");
    assert_eq!(convert.parts as u64, found, "{convert:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn an_asset_with_its_own_parts_keeps_them() {
    let f = fixture().await;
    let mug = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../test_data/examples/mug.glb");
    let sub = f.submit_file(&mug, &pipeline_job_spec()).await;
    let (shutdown, handle) = f.start(
        StageRegistry::pipeline(),
        config(&[("ingest", 1), ("decompose", 1)]),
    );
    let until = Instant::now() + Duration::from_secs(120);
    let decompose = loop {
        let job = f.store.get_job(f.tenant, sub.job_id).await.expect("job");
        let run = job.stage("decompose").expect("stage");
        if run.state == StageState::Succeeded {
            break OutputManifest::from_value(run.output_manifest.as_ref().expect("manifest"))
                .expect("shape");
        }
        assert!(Instant::now() < until, "{:?}", job.stages);
        tokio::time::sleep(Duration::from_millis(50)).await;
    };
    shutdown.cancel();
    handle.await.expect("worker stops");
    let summary: DecomposeStageSummary =
        serde_json::from_value(decompose.summary.clone()).expect("a decompose summary");
    assert!(!summary.decomposed, "{summary:?}");
    assert!(
        summary
            .reason
            .is_some_and(|r| r.contains("kept the input's"))
    );
    assert!(decompose.artifact("face_parts.json").is_none());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn shutdown_releases_runs_that_outlive_the_grace_period() {
    let f = fixture().await;
    let sub = f.submit_slow("slow").await;
    let registry = StageRegistry::stand_ins(&["slow"], Duration::from_secs(30));
    let (shutdown, handle) = f.start(registry, config(&[("slow", 1)]));
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let job = f.store.get_job(f.tenant, sub.job_id).await.expect("job");
        if job.stage("slow").expect("slow").state == StageState::Running {
            break;
        }
        assert!(Instant::now() < until, "never claimed");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    shutdown.cancel();
    tokio::time::timeout(Duration::from_secs(10), handle)
        .await
        .expect("shutdown within grace + release")
        .expect("worker stops");
    let job = f.store.get_job(f.tenant, sub.job_id).await.expect("job");
    let run = job.stage("slow").expect("slow");
    assert_eq!(run.state, StageState::Ready, "released, claimable at once");
    assert_eq!(
        run.max_attempts,
        uniphys_queue::DEFAULT_MAX_ATTEMPTS + 1,
        "the release did not use up an attempt"
    );
    assert!(run.errors.is_empty());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn a_cancel_stops_the_running_stage_and_removes_what_it_wrote() {
    let f = fixture().await;
    let sub = f.submit_slow("cancelled").await;
    // The stand-in writes its artifact first, then works for a minute.
    let registry = StageRegistry::stand_ins(&["slow"], Duration::from_secs(60));
    let (shutdown, handle) = f.start(registry, config(&[("slow", 1)]));
    let prefix = format!("{}/slow/", sub.asset_id.0);
    let until = Instant::now() + Duration::from_secs(20);
    while f.artifacts.list(&prefix).await.expect("list").is_empty() {
        assert!(Instant::now() < until, "the stage never wrote its artifact");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    f.store
        .cancel_job(f.tenant, sub.job_id)
        .await
        .expect("cancel");
    // The worker learns of the cancel at its next heartbeat (a third of the 5 s lease), stops
    // the stage at its next check and removes the object.
    let until = Instant::now() + Duration::from_secs(15);
    loop {
        let left = f.artifacts.list(&prefix).await.expect("list");
        if left.is_empty() {
            break;
        }
        assert!(
            Instant::now() < until,
            "objects of the cancelled run remain: {left:?}"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let job = f.store.get_job(f.tenant, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Cancelled);
    assert!(job.stage("slow").expect("slow").output_manifest.is_none());
    shutdown.cancel();
    tokio::time::timeout(Duration::from_secs(10), handle)
        .await
        .expect("the stopped stage does not hold the worker")
        .expect("worker stops");
}
