//! The worker: for each configured stage, a loop that claims as many runs as it has free slots,
//! runs them ([`crate::execute`]), and otherwise waits for the stage's doorbell or the poll
//! interval; plus a reaper that recovers expired leases. Shutdown stops claiming at once, lets
//! running stages finish within the grace period and releases the rest.

use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use sha2::{Digest, Sha256};
use tokio::sync::Semaphore;
use tokio::task::JoinSet;
use tokio_util::sync::CancellationToken;
use tracing::{info, warn};
use uniphys_hints::{Hints, Wake};
use uniphys_queue::{Completer, DEFAULT_COMPLETION_BATCH, QueueStore, WorkerId};
use uniphys_storage::ArtifactStore;
use uniphys_telemetry::Metrics;

use crate::config::{StageSlots, WorkerConfig};
use crate::execute::execute;
use crate::registry::StageRegistry;
use crate::{WorkerError, WorkerResult};

/// What every task of a worker shares.
pub(crate) struct Shared {
    pub(crate) id: WorkerId,
    pub(crate) store: QueueStore,
    /// Writes the runs' completions, many per transaction when many finish together.
    pub(crate) completer: Completer,
    pub(crate) artifacts: ArtifactStore,
    pub(crate) hints: Hints,
    pub(crate) metrics: Metrics,
    pub(crate) config: WorkerConfig,
}

/// A worker process's claim loops.
pub struct Worker {
    shared: Arc<Shared>,
    registry: StageRegistry,
}

/// A fresh worker identity: unique per process start (never a host or pod name alone).
#[must_use]
pub fn fresh_worker_id() -> WorkerId {
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or_default();
    let host = std::env::var("HOSTNAME").unwrap_or_default();
    let marker = 0u8;
    let seed = format!(
        "{host}/{}/{nanos}/{:p}",
        std::process::id(),
        std::ptr::from_ref(&marker)
    );
    let digest = hex::encode(Sha256::digest(seed.as_bytes()));
    WorkerId(format!("w-{}", &digest[..20]))
}

impl Worker {
    /// A worker running `registry`'s stages as `config` says, with a fresh id. Call it within a
    /// tokio runtime: it starts the task that writes completions in batches.
    pub fn new(
        store: QueueStore,
        artifacts: ArtifactStore,
        hints: Hints,
        metrics: Metrics,
        registry: StageRegistry,
        config: WorkerConfig,
    ) -> WorkerResult<Self> {
        config.validate().map_err(WorkerError::Config)?;
        if let Some(unknown) = config
            .stages
            .iter()
            .find(|s| registry.get(&s.stage).is_none())
        {
            return Err(WorkerError::Config(format!(
                "stage {} is not one this worker can run (known: {})",
                unknown.stage,
                registry.names().join(", ")
            )));
        }
        Ok(Self {
            shared: Arc::new(Shared {
                id: fresh_worker_id(),
                completer: Completer::spawn(store.clone(), DEFAULT_COMPLETION_BATCH),
                store,
                artifacts,
                hints,
                metrics,
                config,
            }),
            registry,
        })
    }

    /// This process's worker id.
    #[must_use]
    pub fn id(&self) -> &WorkerId {
        &self.shared.id
    }

    /// Runs until `shutdown` is cancelled, then drains: returns when every run finished, failed
    /// or was released.
    pub async fn run(self, shutdown: CancellationToken) -> WorkerResult<()> {
        info!(worker = %self.shared.id, stages = ?self.shared.config.stages, "worker started");
        let swept = crate::source::sweep_orphaned_sources(&std::env::temp_dir());
        if swept > 0 {
            info!(
                folders = swept,
                "removed source folders of worker processes that died"
            );
        }
        let mut loops = JoinSet::new();
        for slots in self.shared.config.stages.clone() {
            let stage = self
                .registry
                .get(&slots.stage)
                .ok_or_else(|| WorkerError::Config(format!("unknown stage {}", slots.stage)))?;
            loops.spawn(claim_loop(
                Arc::clone(&self.shared),
                stage,
                slots,
                shutdown.clone(),
            ));
        }
        loops.spawn(reap_loop(Arc::clone(&self.shared), shutdown.clone()));
        while let Some(joined) = loops.join_next().await {
            if let Err(e) = joined {
                warn!(error = %e, "a worker loop ended abnormally");
            }
        }
        info!(worker = %self.shared.id, "worker stopped");
        Ok(())
    }
}

async fn claim_loop(
    shared: Arc<Shared>,
    stage: Arc<dyn crate::Stage>,
    slots: StageSlots,
    shutdown: CancellationToken,
) {
    let names = [slots.stage.as_str()];
    let permits = Arc::new(Semaphore::new(slots.concurrency));
    let mut doorbell = shared.hints.doorbell(std::slice::from_ref(&slots.stage));
    let mut running = JoinSet::new();
    let mut pause = Duration::from_millis(100);
    while !shutdown.is_cancelled() {
        while running.try_join_next().is_some() {}
        let free = permits.available_permits();
        if free == 0 {
            tokio::select! {
                _ = running.join_next() => {}
                () = shutdown.cancelled() => {}
            }
            continue;
        }
        let started = Instant::now();
        let limit = u32::try_from(free).unwrap_or(u32::MAX);
        let claimed = shared
            .store
            .claim(&shared.id, &names, shared.config.lease, limit)
            .await;
        shared
            .metrics
            .observe_claim_latency(&slots.stage, started.elapsed());
        match claimed {
            Ok(runs) if runs.is_empty() => {
                pause = Duration::from_millis(100);
                tokio::select! {
                    wake = doorbell.wait(shared.config.poll_interval) => {
                        if wake == Wake::Rung { continue; }
                    }
                    () = shutdown.cancelled() => {}
                }
            }
            Ok(runs) => {
                pause = Duration::from_millis(100);
                for run in runs {
                    let Ok(permit) = Arc::clone(&permits).acquire_owned().await else {
                        break;
                    };
                    let task = execute(
                        Arc::clone(&shared),
                        Arc::clone(&stage),
                        slots.deadline,
                        run,
                        shutdown.clone(),
                    );
                    running.spawn(async move {
                        task.await;
                        drop(permit);
                    });
                }
            }
            Err(e) => {
                warn!(stage = %slots.stage, error = %e, "claim failed; retrying in {} ms", pause.as_millis());
                tokio::select! {
                    () = tokio::time::sleep(pause) => {}
                    () = shutdown.cancelled() => {}
                }
                pause = (pause * 2).min(Duration::from_secs(5));
            }
        }
    }
    // Drain: running stages finish, or release their runs when the grace period ends.
    while running.join_next().await.is_some() {}
}

async fn reap_loop(shared: Arc<Shared>, shutdown: CancellationToken) {
    let mut tick = tokio::time::interval(shared.config.reap_interval);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        tokio::select! {
            _ = tick.tick() => {}
            () = shutdown.cancelled() => return,
        }
        match shared.store.recover_expired_leases(100).await {
            Ok(report) if report.requeued + report.dead_lettered > 0 => {
                info!(
                    requeued = report.requeued,
                    dead_lettered = report.dead_lettered,
                    "recovered expired leases"
                );
                for slots in &shared.config.stages {
                    if shared.hints.ring(&slots.stage).await.is_err() {
                        shared.metrics.record_hints_error("ring");
                    }
                }
            }
            Ok(_) => {}
            Err(e) => warn!(error = %e, "lease recovery failed; retrying at the next tick"),
        }
    }
}
