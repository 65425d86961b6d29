//! The pipeline as queue stages against the pipeline in one `convert`, in the same run: N assets
//! (the example assets, each moved a little so every file differs) through `ingest → decompose →
//! infer → ground → verify → convert` and through `ingest → decompose → convert` (with no `infer`,
//! `ground` or `verify` upstream, `convert` asks the model, grounds and verifies itself), on one
//! worker with one slot per stage, grounding with the rule-based UniPhysGen test server on
//! loopback. A share of the `convert` runs fails at the end of its first attempt, as a worker
//! killed mid-stage would; the queue retries it. Prints wall time and the model requests each graph
//! sent. The stage graph has three slots more (its `infer`, `ground` and `verify`), so a worker
//! runs stages of different assets at once.
//!
//! `cargo bench -p uniphys_worker --bench stage_pipeline -- [ASSETS] [DATABASE_URL]`
//! (default 100 assets on a temporary SQLite file, the embedded default; with a PostgreSQL URL it
//! runs there too, each graph in a fresh schema it drops at the end).

use std::collections::HashSet;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde_json::Value;
use sqlx::Connection;
use tokio_util::sync::CancellationToken;
use uniphys_examples::{EXAMPLE_NAMES, GlbFrame, example, write_glb};
use uniphys_geometry::{DMat4, DVec3};
use uniphys_hints::Hints;
use uniphys_pipeline::{LearnedOptions, RunOptions};
use uniphys_queue::{JobSpec, JobState, NewAsset, QueueStore, StageSpec, StoreConfig};
use uniphys_storage::ArtifactStore;
use uniphys_telemetry::Metrics;
use uniphys_types::ServiceStage;
use uniphys_uniphysgen::test_server::TestServer;
use uniphys_uniphysgen::{ClientConfig, PointOptions};
use uniphys_worker::stages::{ConvertStage, DecomposeStage};
use uniphys_worker::{
    OutputWriter, Stage, StageControl, StageError, StageInput, StageRegistry, StageSlots, Worker,
    WorkerConfig, pipeline_job_spec,
};

/// Every this many assets, `convert` fails on its first attempt.
const CONVERT_FAILS_EVERY: usize = 5;

/// `convert`, failing at the end of the first attempt of every [`CONVERT_FAILS_EVERY`]-th asset.
struct FlakyConvert {
    stage: ConvertStage,
    failed: Mutex<HashSet<String>>,
}

impl Stage for FlakyConvert {
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
        let digest = input.asset.content_digest.clone();
        let index: usize = digest
            .rsplit('-')
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or(1);
        let summary = self.stage.run(input, out, control)?;
        if index.is_multiple_of(CONVERT_FAILS_EVERY)
            && self.failed.lock().expect("lock").insert(digest)
        {
            // Lost at the end of its work: the retry does it all again.
            return Err(StageError::Transient("the worker was lost".into()));
        }
        Ok(summary)
    }
}

/// The graph without `infer`, `ground` and `verify` stages: `convert` asks the model, grounds and
/// verifies itself.
fn convert_only_spec() -> JobSpec {
    use ServiceStage::{Convert, Decompose, Ingest};
    JobSpec::new(vec![
        StageSpec::new(Ingest.name()).with_max_attempts(3),
        StageSpec::new(Decompose.name())
            .after(Ingest.name())
            .with_max_attempts(3),
        StageSpec::new(Convert.name())
            .after(Ingest.name())
            .after(Decompose.name())
            .with_max_attempts(3),
    ])
}

fn options(model_url: &str) -> RunOptions {
    RunOptions {
        learned: Some(LearnedOptions {
            client: ClientConfig {
                base_url: model_url.to_owned(),
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
    }
}

/// The example files, `n` of them, each example moved by a different millimetre count.
fn asset_files(n: usize) -> Vec<(String, Vec<u8>)> {
    (0..n)
        .map(|i| {
            let name = EXAMPLE_NAMES[i % EXAMPLE_NAMES.len()];
            let mut asset = example(name).expect("example").asset;
            asset.transform(&DMat4::from_translation(DVec3::new(
                0.001 * (i / EXAMPLE_NAMES.len()) as f64,
                0.0,
                0.0,
            )));
            let bytes = write_glb(&asset, GlbFrame::YUp).expect("glb");
            (format!("{name}-{i}"), bytes)
        })
        .collect()
}

/// Outcome of one graph on one store.
struct Outcome {
    wall: Duration,
    succeeded: usize,
    requests: usize,
    convert_attempts: u64,
}

async fn run_graph(
    config: StoreConfig,
    spec: &JobSpec,
    files: &[(String, Vec<u8>)],
    server: &TestServer,
) -> Outcome {
    let store = QueueStore::connect(&config).await.expect("store");
    store.migrate().await.expect("migrate");
    let tenant = store.create_tenant("bench").await.expect("tenant");
    let objects = tempfile::tempdir().expect("objects dir");
    let artifacts = ArtifactStore::local(objects.path()).expect("object store");
    let mut jobs = Vec::new();
    for (name, bytes) in files {
        let key = format!("sources/{name}/{name}.glb");
        artifacts.put(&key, bytes.clone()).await.expect("put");
        let asset = NewAsset {
            content_digest: format!("sha256:{name}"),
            source_uri: key,
            size_bytes: bytes.len() as u64,
        };
        jobs.push(
            store
                .submit(tenant, &asset, spec)
                .await
                .expect("submit")
                .job_id,
        );
    }
    let convert = ConvertStage {
        options: options(&server.url()),
    };
    let registry = StageRegistry::pipeline_with(DecomposeStage::default(), convert.clone()).with(
        FlakyConvert {
            stage: convert,
            failed: Mutex::new(HashSet::new()),
        },
    );
    let slots = ServiceStage::ALL
        .iter()
        .map(|s| StageSlots::new(s.name(), 1))
        .collect();
    let worker = Worker::new(
        store.clone(),
        artifacts,
        Hints::local(),
        Metrics::new(),
        registry,
        WorkerConfig {
            stages: slots,
            lease: Duration::from_secs(30),
            poll_interval: Duration::from_millis(100),
            reap_interval: Duration::from_secs(5),
            shutdown_grace: Duration::from_secs(1),
        },
    )
    .expect("worker");
    let before = server.predict_requests();
    let started = Instant::now();
    let shutdown = CancellationToken::new();
    let token = shutdown.clone();
    let handle = tokio::spawn(async move { worker.run(token).await.expect("worker runs") });
    let (succeeded, convert_attempts) = loop {
        let (mut open, mut succeeded, mut convert_attempts) = (0, 0, 0);
        for job in &jobs {
            let detail = store.get_job(tenant, *job).await.expect("job");
            match detail.state {
                JobState::Running => open += 1,
                JobState::Succeeded => succeeded += 1,
                _ => {}
            }
            convert_attempts += detail
                .stage(ServiceStage::Convert.name())
                .map_or(0, |r| u64::from(r.attempt));
        }
        if open == 0 {
            break (succeeded, convert_attempts);
        }
        tokio::time::sleep(Duration::from_millis(200)).await;
    };
    let wall = started.elapsed();
    shutdown.cancel();
    handle.await.expect("worker stops");
    Outcome {
        wall,
        succeeded,
        requests: server.predict_requests() - before,
        convert_attempts,
    }
}

/// A store config for graph `label`: a fresh SQLite file in `dir`, or a fresh schema at `url`.
async fn fresh_store(
    url: Option<&str>,
    dir: &std::path::Path,
    label: &str,
) -> (StoreConfig, Option<String>) {
    match url {
        None => {
            let path = dir.join(format!("{label}.db"));
            (StoreConfig::new(format!("sqlite:{}", path.display())), None)
        }
        Some(url) => {
            let schema = format!("stage_bench_{}_{label}", std::process::id());
            let mut admin = sqlx::PgConnection::connect(url).await.expect("postgres");
            sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE SCHEMA {schema}")))
                .execute(&mut admin)
                .await
                .expect("schema");
            (
                StoreConfig::new(url.to_owned()).with_schema(schema.clone()),
                Some(schema),
            )
        }
    }
}

#[tokio::main(flavor = "multi_thread")]
async fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let n: usize = args
        .first()
        .map_or(100, |a| a.parse().expect("ASSETS is a count"));
    let url = args.get(1).cloned();
    let server = TestServer::start().expect("UniPhysGen test server");
    let files = asset_files(n);
    let dir = tempfile::tempdir().expect("temp dir");
    println!(
        "# {n} assets, one worker, one slot per stage; convert is lost at the end of its first attempt on every {CONVERT_FAILS_EVERY}th asset\n"
    );
    println!(
        "| store | graph | wall (s) | ratio | succeeded | convert attempts | model requests | ratio |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    let backends: Vec<(&str, Option<&str>)> = std::iter::once(("SQLite (embedded)", None))
        .chain(url.as_deref().map(|u| ("PostgreSQL", Some(u))))
        .collect();
    for (store_name, url) in backends {
        let mut baseline: Option<Outcome> = None;
        for (label, spec) in [
            ("convert", convert_only_spec()),
            ("stages", pipeline_job_spec()),
        ] {
            let (config, schema) = fresh_store(url, dir.path(), label).await;
            let outcome = run_graph(config, &spec, &files, &server).await;
            let graph = if label == "convert" {
                "ingest → decompose → convert (today)"
            } else {
                "ingest → decompose → infer → ground → verify → convert"
            };
            let (wall_ratio, request_ratio) = baseline.as_ref().map_or((1.0, 1.0), |b| {
                (
                    outcome.wall.as_secs_f64() / b.wall.as_secs_f64(),
                    outcome.requests as f64 / b.requests.max(1) as f64,
                )
            });
            println!(
                "| {store_name} | {graph} | {:.1} | {wall_ratio:.2} | {}/{n} | {} | {} | {request_ratio:.2} |",
                outcome.wall.as_secs_f64(),
                outcome.succeeded,
                outcome.convert_attempts,
                outcome.requests
            );
            if let (Some(url), Some(schema)) = (url, schema) {
                let mut admin = sqlx::PgConnection::connect(url).await.expect("postgres");
                sqlx::raw_sql(sqlx::AssertSqlSafe(format!("DROP SCHEMA {schema} CASCADE")))
                    .execute(&mut admin)
                    .await
                    .expect("drop schema");
            }
            baseline.get_or_insert(outcome);
        }
    }
}
