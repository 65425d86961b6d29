//! The apalis side: apalis 1.0 workers (`WorkerBuilder` … `.build(noop)`) on apalis-postgres 1.0
//! storages, one worker per concurrent worker, each fetching up to `batch` tasks at a time
//! (`Config::batch_size`; apalis's default is 10) and acknowledging them in batches, with
//! apalis's defaults otherwise (tasks locked while they run, results persisted). apalis-postgres keeps its tables in
//! its own `apalis` schema (created by `PostgresStorage::setup`); each measurement uses a fresh
//! queue name and deletes its rows afterwards.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context as _, ensure};
use apalis::prelude::{
    BackendExt as _, BoxDynError, Data, TaskSink as _, WorkerBuilder, WorkerContext,
};
use apalis_postgres::{Config, PostgresStorage};
use sqlx::postgres::PgPoolOptions;
use sqlx::{Connection as _, PgPool};
use tokio::task::JoinHandle;

use crate::measure::{
    BACKGROUND_KEY_BASE, LatencyRun, Probes, System, ThroughputRun, WARM_UP, Wakeup, latencies_ms,
};
use crate::rearming_poll::RearmingInterval;
use crate::uniphys_runs::jittered;

/// How long a measurement may wait for its jobs before it fails.
const PATIENCE: Duration = Duration::from_secs(120);
/// How long a stopped worker may take to return.
const STOP_PATIENCE: Duration = Duration::from_secs(15);

/// Start instants of the tasks the workers ran, shared with the handler.
#[derive(Debug)]
struct Recorder {
    started: Mutex<Vec<(u64, Instant)>>,
    expected: usize,
    all_started: tokio::sync::Notify,
}

impl Recorder {
    fn new(expected: u32) -> Arc<Self> {
        Arc::new(Self {
            started: Mutex::new(Vec::new()),
            expected: usize::try_from(expected).unwrap_or(usize::MAX),
            all_started: tokio::sync::Notify::new(),
        })
    }

    /// Records a start; background jobs (keys from [`BACKGROUND_KEY_BASE`]) are not waited for.
    fn record(&self, key: u64, at: Instant) -> Result<(), BoxDynError> {
        if key >= BACKGROUND_KEY_BASE {
            return Ok(());
        }
        let mut started = self.started.lock().map_err(|_| "recorder poisoned")?;
        started.push((key, at));
        if started.len() >= self.expected {
            self.all_started.notify_one();
        }
        Ok(())
    }

    async fn wait_all(&self) -> anyhow::Result<()> {
        tokio::time::timeout(PATIENCE, self.all_started.notified())
            .await
            .with_context(|| format!("apalis: jobs not all started within {PATIENCE:?}"))
    }

    fn take(&self) -> anyhow::Result<Vec<(u64, Instant)>> {
        let mut started = self
            .started
            .lock()
            .map_err(|_| anyhow::anyhow!("poisoned"))?;
        Ok(std::mem::take(&mut *started))
    }
}

/// The task handler: records when it started, does nothing else.
async fn noop(key: u64, recorder: Data<Arc<Recorder>>) -> Result<(), BoxDynError> {
    recorder.record(key, Instant::now())
}

/// A running apalis worker.
type WorkerTask = JoinHandle<anyhow::Result<()>>;

/// A pool, the apalis tables, and a queue name nobody else uses.
struct Scratch {
    url: String,
    pool: PgPool,
    queue: String,
    batch: usize,
}

impl Scratch {
    async fn create(url: &str, pool_size: u32, batch: u32) -> anyhow::Result<Self> {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let pool = PgPoolOptions::new()
            .max_connections(pool_size)
            .connect(url)
            .await?;
        PostgresStorage::<()>::setup(&pool).await?;
        let queue = format!(
            "queue-bench-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        Ok(Self {
            url: url.to_owned(),
            pool,
            queue,
            batch: usize::try_from(batch.max(1)).unwrap_or(1),
        })
    }

    fn storage(&self) -> PostgresStorage<u64> {
        PostgresStorage::new(&self.pool)
            .with_config(Config::default().queue(&self.queue).batch_size(self.batch))
    }

    /// Starts `workers` workers running [`noop`]; stop them through the returned contexts.
    fn spawn_workers(
        &self,
        workers: u32,
        wakeup: Wakeup,
        poll: Duration,
        recorder: &Arc<Recorder>,
    ) -> anyhow::Result<(Vec<WorkerContext>, Vec<WorkerTask>)> {
        ensure!(
            wakeup != Wakeup::Doorbell,
            "apalis has no doorbell of ours; measure it polling or with LISTEN/NOTIFY"
        );
        let mut contexts = Vec::new();
        let mut handles = Vec::new();
        for w in 0..workers {
            let context = WorkerContext::new(&format!("{}-w{w}", self.queue));
            let builder = WorkerBuilder::new(&context);
            let handle = match wakeup {
                Wakeup::Poll | Wakeup::Doorbell => {
                    let worker = builder
                        .backend(self.storage().poll_with_interval(poll))
                        .data(Arc::clone(recorder))
                        .build(noop);
                    tokio::spawn(async move { Ok(worker.run().await?) })
                }
                Wakeup::PollRearmed => {
                    let worker = builder
                        .backend(
                            self.storage()
                                .poll_with_strategy(RearmingInterval::new(poll)),
                        )
                        .data(Arc::clone(recorder))
                        .build(noop);
                    tokio::spawn(async move { Ok(worker.run().await?) })
                }
                Wakeup::Notify => {
                    let worker = builder
                        .backend(self.storage().with_pubsub())
                        .data(Arc::clone(recorder))
                        .build(noop);
                    tokio::spawn(async move { Ok(worker.run().await?) })
                }
            };
            contexts.push(context);
            handles.push(handle);
        }
        Ok((contexts, handles))
    }

    /// Waits until `total` tasks of the queue are `Done` (background tasks the recorder does not
    /// wait for).
    async fn wait_done(&self, total: u64) -> anyhow::Result<()> {
        let deadline = Instant::now() + PATIENCE;
        loop {
            let (done,): (i64,) = sqlx::query_as(
                "SELECT count(*) FROM apalis.jobs WHERE job_type = $1 AND status = 'Done'",
            )
            .bind(&self.queue)
            .fetch_one(&self.pool)
            .await?;
            if u64::try_from(done)? >= total {
                return Ok(());
            }
            ensure!(
                Instant::now() < deadline,
                "apalis: {done} of {total} tasks done after {PATIENCE:?}"
            );
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }

    /// Closes the pool, then on a fresh connection fails unless all `jobs` tasks of the queue are
    /// `Done`, and deletes the queue's rows.
    ///
    /// The pool is closed first: a worker stopped while a fetch was in flight drops that fetch,
    /// and its connection can go back to the pool inside an open transaction; a statement run on
    /// it later would join that transaction and never commit (and the delete would wait forever
    /// on the locks). Closing the connection rolls the stray transaction back.
    async fn check_all_done_and_delete(self, jobs: u32) -> anyhow::Result<()> {
        self.pool.close().await;
        let mut conn = sqlx::PgConnection::connect(&self.url).await?;
        let (done, total): (i64, i64) = sqlx::query_as(
            "SELECT count(*) FILTER (WHERE status = 'Done'), count(*)
             FROM apalis.jobs WHERE job_type = $1",
        )
        .bind(&self.queue)
        .fetch_one(&mut conn)
        .await?;
        sqlx::query("DELETE FROM apalis.jobs WHERE job_type = $1")
            .bind(&self.queue)
            .execute(&mut conn)
            .await?;
        sqlx::query("DELETE FROM apalis.workers WHERE worker_type = $1")
            .bind(&self.queue)
            .execute(&mut conn)
            .await?;
        conn.close().await?;
        ensure!(
            done == i64::from(jobs) && total == i64::from(jobs),
            "apalis: {done} of {total} tasks done, expected {jobs}"
        );
        Ok(())
    }
}

/// A progress line on stderr (the tables go to stdout).
fn progress(queue: &str, what: &str) {
    eprintln!("queue-bench: apalis queue {queue}: {what}");
}

/// Stops the workers and waits until each has flushed its acknowledgements and returned; a worker
/// still running after [`STOP_PATIENCE`] is aborted. Returns how many were aborted.
async fn stop(contexts: &[WorkerContext], handles: Vec<WorkerTask>) -> anyhow::Result<u32> {
    for context in contexts {
        context.stop()?;
    }
    let mut aborted = 0;
    for mut handle in handles {
        match tokio::time::timeout(STOP_PATIENCE, &mut handle).await {
            Ok(joined) => joined??,
            Err(_) => {
                handle.abort();
                aborted += 1;
            }
        }
    }
    Ok(aborted)
}

/// Pre-enqueues `jobs` tasks, then times `workers` workers fetching up to `batch` at a time
/// running them all (until every worker flushed its acknowledgements and returned).
pub(crate) async fn throughput(
    url: &str,
    workers: u32,
    jobs: u32,
    batch: u32,
    wakeup: Wakeup,
    poll: Duration,
) -> anyhow::Result<ThroughputRun> {
    let scratch = Scratch::create(url, workers + 2, batch).await?;
    scratch
        .storage()
        .push_bulk((0..u64::from(jobs)).collect())
        .await?;
    let recorder = Recorder::new(jobs);

    let started = Instant::now();
    let (contexts, handles) = scratch.spawn_workers(workers, wakeup, poll, &recorder)?;
    recorder.wait_all().await?;
    let aborted = stop(&contexts, handles).await?;
    let elapsed = started.elapsed();
    ensure!(
        aborted == 0,
        "apalis: {aborted} workers did not stop within {STOP_PATIENCE:?}"
    );

    scratch.check_all_done_and_delete(jobs).await?;
    let executed = recorder.take()?.into_iter().map(|(key, _)| key).collect();
    Ok(ThroughputRun {
        system: System::Apalis,
        workers,
        elapsed,
        executed,
    })
}

/// Pushes `probes.jobs` tasks one at a time, `probes.gap` apart on average, to `probes.workers`
/// workers woken by `wakeup`, while a background task pushes `probes.load_per_sec` other tasks a
/// second; measures from calling push until the handler started a probe task.
pub(crate) async fn latency(
    url: &str,
    probes: Probes,
    wakeup: Wakeup,
) -> anyhow::Result<LatencyRun> {
    let scratch = Scratch::create(url, probes.workers + 3, 1).await?;
    let recorder = Recorder::new(probes.jobs);
    let (contexts, handles) =
        scratch.spawn_workers(probes.workers, wakeup, probes.poll, &recorder)?;

    tokio::time::sleep(WARM_UP).await;
    let load_stop = Arc::new(AtomicBool::new(false));
    let load = tokio::spawn(background_load(
        scratch.storage(),
        probes.load_per_sec,
        Arc::clone(&load_stop),
    ));
    let mut sink = scratch.storage();
    let mut submitted = Vec::new();
    let mut submit_ms = Vec::new();
    for key in 0..u64::from(probes.jobs) {
        tokio::time::sleep(jittered(probes.gap, key)).await;
        let sent = Instant::now();
        sink.push(key).await?;
        submit_ms.push(sent.elapsed().as_secs_f64() * 1e3);
        submitted.push(sent);
    }
    load_stop.store(true, Ordering::Relaxed);
    let background_jobs = load.await??;
    recorder.wait_all().await?;
    // The background tasks finish too before the workers stop (they are checked done below).
    let total = u64::from(probes.jobs) + background_jobs as u64;
    scratch.wait_done(total).await?;
    progress(&scratch.queue, "all started; stopping the workers");
    let stuck_workers = stop(&contexts, handles).await?;
    if stuck_workers > 0 {
        progress(
            &scratch.queue,
            &format!("{stuck_workers} workers did not stop within {STOP_PATIENCE:?}; aborted"),
        );
    }

    scratch
        .check_all_done_and_delete(u32::try_from(total)?)
        .await?;
    let started = recorder.take()?;
    Ok(LatencyRun {
        system: System::Apalis,
        wakeup,
        enqueue_to_start_ms: latencies_ms(&submitted, &started)?,
        submit_ms,
        executed: started.into_iter().map(|(key, _)| key).collect(),
        background_jobs,
        load_per_sec: probes.load_per_sec,
        stuck_workers,
    })
}

/// Pushes background tasks (keys from [`BACKGROUND_KEY_BASE`]) at `per_sec` a second until
/// `stop`; returns how many.
async fn background_load(
    mut sink: PostgresStorage<u64>,
    per_sec: u32,
    stop: Arc<AtomicBool>,
) -> anyhow::Result<usize> {
    if per_sec == 0 {
        return Ok(0);
    }
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / f64::from(per_sec)));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut key = BACKGROUND_KEY_BASE;
    while !stop.load(Ordering::Relaxed) {
        tick.tick().await;
        sink.push(key).await?;
        key += 1;
    }
    Ok(usize::try_from(key - BACKGROUND_KEY_BASE)?)
}
