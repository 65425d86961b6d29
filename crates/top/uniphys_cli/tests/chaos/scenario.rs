//! One chaos run: N assets through stand-ins of the pipeline's stages (ingest → decompose →
//! infer → ground → verify → convert) on several `uniphys worker` processes, SIGKILLs at random,
//! optionally Redis stopped or PostgreSQL restarted midway; then every output is checked against
//! its recipe.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use sha2::{Digest, Sha256};
use sqlx::Row;
use sqlx::postgres::PgPoolOptions;
use uniphys_queue::{JobSpec, NewAsset, QueueStore, RetryPolicy, StoreConfig};

use super::servers::{PgCluster, RedisServer};
use super::workers::{WorkerEnv, WorkerProcess};

/// The pipeline's stages, by name, in order.
const STAGES: [&str; 6] = [
    "ingest",
    "decompose",
    "infer",
    "ground",
    "verify",
    "convert",
];
/// The files a `convert` stand-in writes besides its `out.txt`: the dataset entity.
const ENTITY_FILES: [&str; 3] = ["object.json", "record.json", "report.json"];

/// What to do to the system while it runs.
#[derive(Clone, Copy, Debug)]
pub struct Scenario {
    pub name: &'static str,
    pub assets: usize,
    pub workers: usize,
    pub kill_every: Duration,
    pub stop_redis_midway: bool,
    pub restart_postgres_midway: bool,
}

/// What happened.
#[derive(Debug)]
pub struct Outcome {
    pub elapsed: Duration,
    pub kills: usize,
    pub recovery_secs: Vec<f64>,
    pub reclaim_secs: Vec<f64>,
    pub extra_executions: i64,
    pub runs: i64,
}

struct Kill {
    at: Instant,
    held: Vec<(i64, i64)>,
    /// Every held run was put back (no longer leased to the dead worker).
    recovered_after: Option<Duration>,
    /// Every held run was claimed again (it waits its turn behind older ready runs).
    reclaimed_after: Option<Duration>,
}

/// A small deterministic generator (xorshift), so a failing run can be replayed by seed.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

fn expected_output(stage: &str, content_digest: &str, upstream: &[(&str, String)]) -> Vec<u8> {
    let mut hasher = Sha256::new();
    hasher.update(content_digest.as_bytes());
    for (name, sha) in upstream {
        hasher.update(name.as_bytes());
        hasher.update(sha.as_bytes());
    }
    format!("{stage}:{}\n", hex::encode(hasher.finalize())).into_bytes()
}

pub async fn run(scenario: Scenario) -> Outcome {
    let pg = PgCluster::start();
    let mut redis = RedisServer::start();
    let storage = tempfile::tempdir().expect("storage dir");
    let lease_secs = 2;
    let retry = RetryPolicy {
        base_delay: Duration::from_millis(200),
        max_delay: Duration::from_secs(2),
    };
    let store = QueueStore::connect(&StoreConfig::new(pg.url()).with_retry(retry))
        .await
        .expect("store");
    store.migrate().await.expect("migrate");
    let tenant = store.create_tenant("chaos").await.expect("tenant");
    let spec = JobSpec::chain(&STAGES);
    for i in 0..scenario.assets {
        let asset = NewAsset {
            content_digest: format!("sha256:chaos-{i}"),
            source_uri: format!("sources/chaos-{i}"),
            size_bytes: 1,
        };
        store.submit(tenant, &asset, &spec).await.expect("submit");
    }
    store.close().await;
    let pool = PgPoolOptions::new()
        .max_connections(2)
        .connect(&pg.url())
        .await
        .expect("observer pool");

    let env = WorkerEnv {
        database_url: pg.url(),
        storage_dir: storage.path().to_path_buf(),
        redis_url: Some(redis.url()),
        stages: STAGES.to_vec(),
        work_ms: 10,
        lease_secs,
        slots_per_stage: 4,
    };
    let started = Instant::now();
    let mut workers: Vec<WorkerProcess> = (0..scenario.workers)
        .map(|_| WorkerProcess::start(&env))
        .collect();
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    let mut kills: Vec<Kill> = Vec::new();
    let mut next_kill = Instant::now() + scenario.kill_every;
    let mut disturbed = false;
    let total_runs = (scenario.assets * STAGES.len()) as i64;
    let deadline = Instant::now() + Duration::from_secs(300);
    loop {
        tokio::time::sleep(Duration::from_millis(50)).await;
        let Ok(row) = sqlx::query(
            "SELECT count(*) FILTER (WHERE state = 'succeeded') AS done,
                    count(*) FILTER (WHERE state = 'dead') AS dead
             FROM stage_runs",
        )
        .fetch_one(&pool)
        .await
        else {
            continue; // the database is restarting
        };
        let done: i64 = row.get("done");
        let dead: i64 = row.get("dead");
        assert_eq!(dead, 0, "{}: a stage run was dead-lettered", scenario.name);
        for kill in kills.iter_mut().filter(|k| k.reclaimed_after.is_none()) {
            let ids: Vec<i64> = kill.held.iter().map(|(id, _)| *id).collect();
            let Ok(rows) =
                sqlx::query("SELECT id, attempt, state FROM stage_runs WHERE id = ANY($1)")
                    .bind(&ids)
                    .fetch_all(&pool)
                    .await
            else {
                continue;
            };
            let before: BTreeMap<i64, i64> = kill.held.iter().copied().collect();
            let state_of = |r: &sqlx::postgres::PgRow| -> (bool, bool) {
                let id: i64 = r.get("id");
                let attempt: i64 = r.get("attempt");
                let state: String = r.get("state");
                let reclaimed = attempt > before[&id] || state == "succeeded";
                (reclaimed || state != "running", reclaimed)
            };
            if kill.recovered_after.is_none() && rows.iter().all(|r| state_of(r).0) {
                kill.recovered_after = Some(kill.at.elapsed());
            }
            if rows.iter().all(|r| state_of(r).1) {
                kill.reclaimed_after = Some(kill.at.elapsed());
                kill.recovered_after.get_or_insert(kill.at.elapsed());
            }
        }
        if done == total_runs {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "{}: only {done} of {total_runs} runs done after 300 s",
            scenario.name
        );
        if !disturbed && done * 2 >= total_runs {
            disturbed = true;
            if scenario.stop_redis_midway {
                redis.stop();
                eprintln!("{}: Redis stopped at {done}/{total_runs}", scenario.name);
            }
            if scenario.restart_postgres_midway {
                pg.restart();
                eprintln!(
                    "{}: PostgreSQL restarted at {done}/{total_runs}",
                    scenario.name
                );
            }
        }
        if Instant::now() >= next_kill {
            next_kill = Instant::now() + scenario.kill_every;
            let victim = workers.swap_remove(rng.below(workers.len()));
            let held: Vec<(i64, i64)> = match sqlx::query(
                "SELECT id, attempt FROM stage_runs WHERE state = 'running' AND worker_id = $1",
            )
            .bind(&victim.id)
            .fetch_all(&pool)
            .await
            {
                Ok(rows) => rows
                    .iter()
                    .map(|r| (r.get("id"), r.get("attempt")))
                    .collect(),
                Err(_) => Vec::new(),
            };
            victim.kill();
            if !held.is_empty() {
                kills.push(Kill {
                    at: Instant::now(),
                    held,
                    recovered_after: None,
                    reclaimed_after: None,
                });
            }
            workers.push(WorkerProcess::start(&env));
        }
    }
    let elapsed = started.elapsed();
    let kill_count = kills.len();
    for worker in workers {
        let status = worker.terminate();
        assert!(
            status.success(),
            "a worker did not shut down cleanly: {status}"
        );
    }

    // Every job succeeded, every output matches its recipe, and each run wrote one key.
    let rows = sqlx::query(
        "SELECT a.content_digest, r.stage_name, r.attempt, r.output_manifest::text AS manifest, j.state
         FROM stage_runs r JOIN assets a ON a.id = r.asset_id JOIN jobs j ON j.id = r.job_id
         ORDER BY r.asset_id, r.id",
    )
    .fetch_all(&pool)
    .await
    .expect("final rows");
    assert_eq!(rows.len() as i64, total_runs);
    let mut attempts = 0i64;
    let mut previous: Vec<(&str, String)> = Vec::new();
    let mut last_asset = String::new();
    for row in &rows {
        let digest: String = row.get("content_digest");
        let stage: String = row.get("stage_name");
        let job_state: String = row.get("state");
        assert_eq!(job_state, "succeeded");
        attempts += row.get::<i64, _>("attempt");
        if digest != last_asset {
            previous.clear();
            last_asset = digest.clone();
        }
        let manifest: serde_json::Value =
            serde_json::from_str(&row.get::<String, _>("manifest")).expect("manifest json");
        let artifact = manifest["artifacts"]
            .as_array()
            .into_iter()
            .flatten()
            .find(|a| a["name"] == "out.txt")
            .expect("every stand-in writes out.txt");
        let key = artifact["key"].as_str().expect("key");
        let bytes = std::fs::read(storage.path().join(key)).expect("output exists");
        let sha = hex::encode(Sha256::digest(&bytes));
        assert_eq!(artifact["sha256"].as_str(), Some(sha.as_str()), "{key}");
        let upstream: Vec<(&str, String)> = previous.last().cloned().into_iter().collect();
        assert_eq!(bytes, expected_output(&stage, &digest, &upstream), "{key}");
        let stage_name: &str = STAGES.iter().find(|s| **s == stage).expect("known stage");
        previous.push((stage_name, sha));
    }
    let mut files = Vec::new();
    walk_files(storage.path(), &mut files);
    let (outputs, stray): (Vec<_>, Vec<_>) = files
        .iter()
        .filter(|p| {
            !p.file_name()
                .is_some_and(|n| ENTITY_FILES.iter().any(|e| n == *e))
        })
        .partition(|p| p.file_name().is_some_and(|n| n == "out.txt"));
    assert_eq!(
        outputs.len() as i64,
        total_runs,
        "one object per run: re-runs rewrote the same key"
    );
    // A kill between the object store's temporary file and its rename leaves the temporary
    // (`<name>#<n>`).
    assert!(
        stray.iter().all(|p| p
            .file_name()
            .is_some_and(|n| n.to_string_lossy().contains('#'))),
        "unexpected objects: {stray:?}"
    );
    if !stray.is_empty() {
        eprintln!(
            "{}: {} temporary files left by killed writers",
            scenario.name,
            stray.len()
        );
    }
    pool.close().await;
    drop(redis);
    Outcome {
        elapsed,
        kills: kill_count,
        recovery_secs: kills
            .iter()
            .map(|k| {
                k.recovered_after
                    .expect("every killed worker's runs came back")
                    .as_secs_f64()
            })
            .collect(),
        reclaim_secs: kills
            .iter()
            .map(|k| {
                k.reclaimed_after
                    .expect("every killed worker's runs ran again")
                    .as_secs_f64()
            })
            .collect(),
        extra_executions: attempts - total_runs,
        runs: total_runs,
    }
}

fn walk_files(dir: &std::path::Path, files: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            walk_files(&path, files);
        } else {
            files.push(path);
        }
    }
}
