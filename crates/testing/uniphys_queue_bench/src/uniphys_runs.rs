//! The UniPhys queue's side: workers are tokio tasks looping `claim` (up to the batch size) →
//! `complete` of each claimed run through one shared [`Completer`] (empty manifests), as the
//! service's worker does, on one-stage `noop` jobs, each job submitted with its own asset.
//! Latency is measured with the workers polling, and with them woken by the service's doorbell
//! (`uniphys_hints` on Redis, rung after each submit as the API does).

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context as _, ensure};
use serde_json::json;
use sqlx::Connection as _;
use tokio::task::JoinSet;
use uniphys_hints::{Hints, Wake};
use uniphys_queue::{
    Completer, DEFAULT_COMPLETION_BATCH, JobId, JobSpec, NewAsset, QueueStore, StageCost,
    StoreConfig, TenantId, WorkerId,
};

use crate::measure::{
    BACKGROUND_KEY_BASE, DOORBELL_POLL, LatencyRun, Probes, System, ThroughputRun, WARM_UP, Wakeup,
    latencies_ms,
};

const STAGE: &str = "noop";
const LEASE: Duration = Duration::from_secs(60);
/// Concurrent submitters while pre-enqueueing a throughput backlog (not timed).
const SUBMITTERS: u64 = 8;

/// A store in a fresh schema of its own, dropped by [`Scratch::drop_schema`].
struct Scratch {
    url: String,
    schema: String,
    store: QueueStore,
    tenant: TenantId,
}

impl Scratch {
    async fn create(url: &str, pool_size: u32) -> anyhow::Result<Self> {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let schema = format!(
            "queue_bench_{}_{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let mut admin = sqlx::PgConnection::connect(url).await?;
        sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE SCHEMA {schema}")))
            .execute(&mut admin)
            .await?;
        admin.close().await?;
        let config = StoreConfig::new(url)
            .with_schema(schema.clone())
            .with_max_connections(pool_size);
        let store = QueueStore::connect(&config).await?;
        store.migrate().await?;
        let tenant = store.create_tenant("queue-bench").await?;
        Ok(Self {
            url: url.to_owned(),
            schema,
            store,
            tenant,
        })
    }

    async fn submit(&self, key: u64) -> anyhow::Result<JobId> {
        let asset = NewAsset {
            content_digest: format!("sha256:{key:064x}"),
            source_uri: format!("queue-bench/{key}"),
            size_bytes: 1,
        };
        let submission = self
            .store
            .submit(self.tenant, &asset, &JobSpec::chain(&[STAGE]))
            .await?;
        ensure!(submission.job_created, "job {key} was not created");
        Ok(submission.job_id)
    }

    /// Fails unless all `jobs` stage runs succeeded after exactly one claim each.
    async fn check_all_succeeded_once(&self, jobs: u32) -> anyhow::Result<()> {
        let mut conn = sqlx::PgConnection::connect(&self.url).await?;
        let (once, total): (i64, i64) = sqlx::query_as(sqlx::AssertSqlSafe(format!(
            "SELECT count(*) FILTER (WHERE state = 'succeeded' AND attempt = 1), count(*)
             FROM {}.stage_runs",
            self.schema
        )))
        .fetch_one(&mut conn)
        .await?;
        ensure!(
            once == i64::from(jobs) && total == i64::from(jobs),
            "uniphys: {once} of {total} stage runs succeeded on their first claim, expected {jobs}"
        );
        Ok(())
    }

    async fn drop_schema(self) -> anyhow::Result<()> {
        self.store.close().await;
        let mut admin = sqlx::PgConnection::connect(&self.url).await?;
        sqlx::raw_sql(sqlx::AssertSqlSafe(format!(
            "DROP SCHEMA {} CASCADE",
            self.schema
        )))
        .execute(&mut admin)
        .await?;
        Ok(())
    }
}

/// Pre-enqueues `jobs` jobs, then times `workers` workers running them all, each claiming up to
/// `batch` runs at a time.
pub(crate) async fn throughput(
    url: &str,
    workers: u32,
    jobs: u32,
    batch: u32,
) -> anyhow::Result<ThroughputRun> {
    let scratch = Arc::new(Scratch::create(url, workers.max(SUBMITTERS as u32) + 2).await?);
    let mut submitters = Vec::new();
    for first in 0..SUBMITTERS {
        let scratch = Arc::clone(&scratch);
        submitters.push(tokio::spawn(async move {
            let mut ids = Vec::new();
            for key in (first..u64::from(jobs)).step_by(SUBMITTERS as usize) {
                ids.push((scratch.submit(key).await?, key));
            }
            anyhow::Ok(ids)
        }));
    }
    let mut key_of: HashMap<JobId, u64> = HashMap::new();
    for task in submitters {
        key_of.extend(task.await??);
    }

    let started = Instant::now();
    let completer = Completer::spawn(scratch.store.clone(), DEFAULT_COMPLETION_BATCH);
    let mut tasks = Vec::new();
    for w in 0..workers {
        let store = scratch.store.clone();
        let completer = completer.clone();
        tasks.push(tokio::spawn(async move {
            let me = WorkerId(format!("queue-bench-{w}"));
            let mut ran = Vec::new();
            loop {
                let claimed = store.claim(&me, &[STAGE], LEASE, batch).await?;
                // The backlog was enqueued before the workers started: nothing ready means done
                // (a run another claim holds is skipped, and that claimer completes it).
                if claimed.is_empty() {
                    return anyhow::Ok(ran);
                }
                // Each claimed run finishes on its own, as a worker's stage tasks do.
                let mut finishing = JoinSet::new();
                for run in claimed {
                    let completer = completer.clone();
                    finishing.spawn(async move {
                        completer
                            .complete(&run.lease, &json!({}), &StageCost::default())
                            .await
                            .map(|_| run.job_id)
                    });
                }
                while let Some(done) = finishing.join_next().await {
                    ran.push(done??);
                }
            }
        }));
    }
    let mut ran = Vec::new();
    for task in tasks {
        ran.extend(task.await??);
    }
    let elapsed = started.elapsed();

    scratch.check_all_succeeded_once(jobs).await?;
    let executed = keys(&ran, &key_of)?;
    Arc::into_inner(scratch)
        .context("scratch store still shared")?
        .drop_schema()
        .await?;
    Ok(ThroughputRun {
        system: System::Uniphys,
        workers,
        elapsed,
        executed,
    })
}

/// Submits `probes.jobs` jobs one at a time, `probes.gap` apart on average, to `probes.workers`
/// workers that poll every `probes.poll` or, with `doorbell`, wait on it between polls every
/// [`DOORBELL_POLL`] (the submitter rings it after each submit), while a background submitter adds
/// `probes.load_per_sec` other jobs a second; measures from calling submit until `claim` returned
/// a probe job.
pub(crate) async fn latency(
    url: &str,
    probes: Probes,
    doorbell: Option<&Hints>,
) -> anyhow::Result<LatencyRun> {
    let scratch = Arc::new(Scratch::create(url, probes.workers + 3).await?);
    let stop = Arc::new(AtomicBool::new(false));
    let started: Arc<Mutex<Vec<(JobId, Instant)>>> = Arc::default();
    let mut tasks = Vec::new();
    for w in 0..probes.workers {
        let store = scratch.store.clone();
        let stop = Arc::clone(&stop);
        let started = Arc::clone(&started);
        let mut bell = doorbell.map(|hints| hints.doorbell(&[STAGE.to_owned()]));
        let poll = if bell.is_some() {
            DOORBELL_POLL
        } else {
            probes.poll
        };
        tasks.push(tokio::spawn(async move {
            let me = WorkerId(format!("queue-bench-{w}"));
            while !stop.load(Ordering::Relaxed) {
                let claimed = store.claim(&me, &[STAGE], LEASE, 1).await?;
                let at = Instant::now();
                let Some(run) = claimed.first() else {
                    match bell.as_mut() {
                        Some(bell) => {
                            let _: Wake = bell.wait(poll).await;
                        }
                        None => tokio::time::sleep(poll).await,
                    }
                    continue;
                };
                started
                    .lock()
                    .map_err(|_| anyhow::anyhow!("poisoned"))?
                    .push((run.job_id, at));
                store
                    .complete(&run.lease, &json!({}), &StageCost::default())
                    .await?;
            }
            anyhow::Ok(())
        }));
    }

    tokio::time::sleep(WARM_UP).await;
    let load_stop = Arc::new(AtomicBool::new(false));
    let load = tokio::spawn(background_load(
        Arc::clone(&scratch),
        probes.load_per_sec,
        Arc::clone(&load_stop),
    ));
    let mut submitted = Vec::new();
    let mut submit_ms = Vec::new();
    let mut key_of: HashMap<JobId, u64> = HashMap::new();
    for key in 0..u64::from(probes.jobs) {
        tokio::time::sleep(jittered(probes.gap, key)).await;
        let sent = Instant::now();
        let job = scratch.submit(key).await?;
        if let Some(hints) = doorbell {
            // A hint: if it fails, the workers' poll still finds the job.
            let _ = hints.ring(STAGE).await;
        }
        submit_ms.push(sent.elapsed().as_secs_f64() * 1e3);
        submitted.push(sent);
        key_of.insert(job, key);
    }
    load_stop.store(true, Ordering::Relaxed);
    let background = load.await??;
    let background_jobs = background.len();
    key_of.extend(background);
    let deadline = Instant::now() + Duration::from_secs(30);
    while started
        .lock()
        .map_err(|_| anyhow::anyhow!("poisoned"))?
        .len()
        < key_of.len()
    {
        ensure!(
            Instant::now() < deadline,
            "uniphys: jobs not started within 30 s"
        );
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    stop.store(true, Ordering::Relaxed);
    for task in tasks {
        task.await??;
    }

    let total = u32::try_from(key_of.len())?;
    scratch.check_all_succeeded_once(total).await?;
    let started = std::mem::take(&mut *started.lock().map_err(|_| anyhow::anyhow!("poisoned"))?);
    let ids: Vec<JobId> = started.iter().map(|(id, _)| *id).collect();
    let by_key: Vec<(u64, Instant)> = keys(&ids, &key_of)?
        .into_iter()
        .zip(&started)
        .map(|(key, (_, at))| (key, *at))
        .filter(|(key, _)| *key < BACKGROUND_KEY_BASE)
        .collect();
    Arc::into_inner(scratch)
        .context("scratch store still shared")?
        .drop_schema()
        .await?;
    Ok(LatencyRun {
        system: System::Uniphys,
        wakeup: if doorbell.is_some() {
            Wakeup::Doorbell
        } else {
            Wakeup::Poll
        },
        enqueue_to_start_ms: latencies_ms(&submitted, &by_key)?,
        submit_ms,
        executed: by_key.iter().map(|(key, _)| *key).collect(),
        background_jobs,
        load_per_sec: probes.load_per_sec,
        stuck_workers: 0,
    })
}

/// Submits background jobs (keys from [`BACKGROUND_KEY_BASE`]) at `per_sec` a second until
/// `stop`; returns them.
async fn background_load(
    scratch: Arc<Scratch>,
    per_sec: u32,
    stop: Arc<AtomicBool>,
) -> anyhow::Result<Vec<(JobId, u64)>> {
    let mut submitted = Vec::new();
    if per_sec == 0 {
        return Ok(submitted);
    }
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / f64::from(per_sec)));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut key = BACKGROUND_KEY_BASE;
    while !stop.load(Ordering::Relaxed) {
        tick.tick().await;
        submitted.push((scratch.submit(key).await?, key));
        key += 1;
    }
    Ok(submitted)
}

/// `gap` ± 5 ms, varying with `key` (deterministic, so runs are comparable).
pub(crate) fn jittered(gap: Duration, key: u64) -> Duration {
    let offset_ms = (key * 7) % 11;
    (gap + Duration::from_millis(offset_ms)).saturating_sub(Duration::from_millis(5))
}

fn keys(ran: &[JobId], key_of: &HashMap<JobId, u64>) -> anyhow::Result<Vec<u64>> {
    ran.iter()
        .map(|job| {
            key_of
                .get(job)
                .copied()
                .with_context(|| format!("uniphys: claimed unknown job {job:?}"))
        })
        .collect()
}
