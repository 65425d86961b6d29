//! One claimed run, start to end: read its context, run the stage on a blocking thread while
//! renewing the lease and relaying progress, then complete, fail or release it — each a short,
//! fenced statement, retried while the database is unreachable.

use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio_util::sync::CancellationToken;
use tracing::{Instrument, info, warn};
use uniphys_hints::Progress;
use uniphys_queue::{
    ClaimedRun, FailOutcome, MAX_MANIFEST_BYTES, OutputManifest, QueueError, QueueErrorKind,
    QueueResult, StageCost, StageFailure, oversized_manifest_bytes,
};
use uniphys_telemetry::{StageOutcome, stage_span};

use crate::outputs::OutputWriter;
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::worker::Shared;

/// Why the stage's thread stopped early.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Interrupt {
    /// Lease lost or job cancelled: someone else owns the run now.
    Fenced(StageOutcome),
    /// Past the stage's deadline.
    Deadline,
    /// Worker shutdown and the grace period is over.
    Shutdown,
}

/// Runs `run` of `stage` to its end (or until shutdown releases it).
pub(crate) async fn execute(
    shared: Arc<Shared>,
    stage: Arc<dyn Stage>,
    deadline: Duration,
    run: ClaimedRun,
    shutdown: CancellationToken,
) {
    let context = match retry_db(&shared, "read the run's context", || {
        shared.store.run_context(run.lease.run_id)
    })
    .await
    {
        Ok(context) => context,
        Err(e) => {
            // The lease will expire and the run be recovered elsewhere.
            warn!(run = %run.lease.run_id, error = %e, "cannot read the run's context; leaving it to lease recovery");
            return;
        }
    };
    let span = stage_span(
        &run.stage_name,
        run.job_id.0,
        run.lease.run_id.0,
        run.lease.attempt,
        context.trace_parent.as_deref(),
    );
    async move {
        let started = Instant::now();
        let input = StageInput {
            asset: context.asset,
            job_id: context.job_id.0,
            upstream: context
                .upstream
                .iter()
                .map(|(name, value)| {
                    (name.clone(), OutputManifest::from_value(value).unwrap_or_default())
                })
                .collect(),
            artifacts: shared.artifacts.clone(),
            runtime: tokio::runtime::Handle::current(),
        };
        let (control, mut progress) = StageControl::new();
        let thread_control = control.clone();
        let thread_stage = Arc::clone(&stage);
        let mut task = tokio::task::spawn_blocking(move || {
            let mut out = OutputWriter::new(&input, thread_stage.name(), thread_stage.version());
            let result = thread_stage.run(&input, &mut out, &thread_control);
            let created = out.created_keys();
            (result.map(|summary| out.into_manifest(summary)), created)
        });

        let mut heartbeat = tokio::time::interval(shared.config.lease / 3);
        heartbeat.tick().await;
        let deadline_at = tokio::time::sleep(deadline);
        tokio::pin!(deadline_at);
        let grace_over = async {
            shutdown.cancelled().await;
            tokio::time::sleep(shared.config.shutdown_grace).await;
        };
        tokio::pin!(grace_over);
        let mut interrupt = None;
        let result = loop {
            tokio::select! {
                joined = &mut task => break joined,
                _ = heartbeat.tick() => {
                    match shared.store.heartbeat(&run.lease, shared.config.lease).await {
                        Ok(_) => {}
                        Err(e @ (QueueError::LeaseLost { .. } | QueueError::Cancelled { .. })) => {
                            let outcome = if matches!(e, QueueError::Cancelled { .. }) {
                                StageOutcome::Cancelled
                            } else {
                                StageOutcome::LeaseLost
                            };
                            interrupt.get_or_insert(Interrupt::Fenced(outcome));
                            control.stop();
                        }
                        // The database is away: keep going, the lease may outlive the outage.
                        Err(e) => warn!(error = %e, "heartbeat failed; retrying at the next beat"),
                    }
                }
                Ok(()) = progress.changed() => {
                    let now = progress.borrow_and_update().clone();
                    let update = Progress::new(now.fraction, now.message);
                    if shared.hints.set_progress(run.job_id.0, &run.stage_name, &update).await.is_err() {
                        shared.metrics.record_hints_error("set_progress");
                    }
                }
                () = &mut deadline_at, if interrupt.is_none() => {
                    interrupt = Some(Interrupt::Deadline);
                    control.stop();
                }
                () = &mut grace_over, if interrupt.is_none() => {
                    interrupt = Some(Interrupt::Shutdown);
                    control.stop();
                    // The stage thread cannot be killed; hand the run back now and stop waiting.
                    break Ok((Err(StageError::Stopped), Vec::new()));
                }
            }
        };
        let elapsed = started.elapsed();
        let outcome = finish(&shared, &run, result, interrupt, deadline).await;
        if let Some(outcome) = outcome {
            shared
                .metrics
                .record_stage_attempt(&run.stage_name, outcome, run.lease.attempt, elapsed);
        }
    }
    .instrument(span)
    .await;
}

/// What a stage thread returns: its manifest or error, and the keys of the objects it created.
type StageResult =
    Result<(Result<OutputManifest, StageError>, Vec<String>), tokio::task::JoinError>;

/// Records how the run ended; `None` when it was released or left to lease recovery.
async fn finish(
    shared: &Shared,
    run: &ClaimedRun,
    result: StageResult,
    interrupt: Option<Interrupt>,
    deadline: Duration,
) -> Option<StageOutcome> {
    let (result, created) = match result {
        Ok((outcome, created)) => (Ok(outcome), created),
        Err(join) => (Err(join), Vec::new()),
    };
    if let Some(Interrupt::Fenced(outcome)) = interrupt {
        info!("the run was taken away (lease lost or cancelled); its result is dropped");
        if outcome == StageOutcome::Cancelled {
            remove_created(shared, &created).await;
        }
        return Some(outcome);
    }
    let failure = match result {
        Ok(Ok(manifest)) => {
            let value = manifest.to_value();
            if let Some(bytes) = oversized_manifest_bytes(&value) {
                // The store refuses it every time: failing now names why, where a refused
                // completion would leave the run to lease recovery again and again.
                StageFailure::permanent(format!(
                    "the stage's output manifest is {bytes} bytes, over the queue's {MAX_MANIFEST_BYTES}: its summary must name artifacts, not hold data (a stage bug)"
                ))
            } else {
                let cost = StageCost::default();
                let done = retry_db(shared, "complete the run", || {
                    shared.completer.complete(&run.lease, &value, &cost)
                })
                .await;
                return match done {
                    Ok(outcome) => {
                        for next in &outcome.unblocked {
                            if shared.hints.ring(&next.stage_name).await.is_err() {
                                shared.metrics.record_hints_error("ring");
                            }
                        }
                        Some(StageOutcome::Succeeded)
                    }
                    Err(e) => Some(dropped(shared, &e, &created).await),
                };
            }
        }
        Ok(Err(StageError::Stopped)) => match interrupt {
            Some(Interrupt::Shutdown) | None => {
                match retry_db(shared, "release the run", || {
                    shared.store.release(&run.lease)
                })
                .await
                {
                    Ok(()) => info!("released on shutdown"),
                    Err(e) => warn!(error = %e, "release failed; lease recovery will put it back"),
                }
                return None;
            }
            _ => StageFailure::transient(format!(
                "stopped after its deadline of {} s",
                deadline.as_secs()
            )),
        },
        Ok(Err(StageError::Transient(message))) => StageFailure::transient(message),
        Ok(Err(StageError::Permanent(message))) => StageFailure::permanent(message),
        Err(join) => StageFailure::transient(format!("the stage panicked: {join}")),
    };
    match retry_db(shared, "record the failure", || {
        shared.store.fail(&run.lease, &failure)
    })
    .await
    {
        Ok(FailOutcome::RetryScheduled { .. }) => Some(StageOutcome::Retrying),
        Ok(FailOutcome::DeadLettered) => Some(StageOutcome::Dead),
        Err(e) => Some(dropped(shared, &e, &created).await),
    }
}

/// The outcome of a run whose end the store refused with `e`; a cancelled run's objects
/// (`created`) are removed.
async fn dropped(shared: &Shared, e: &QueueError, created: &[String]) -> StageOutcome {
    let outcome = fenced_or_lost(e);
    if outcome == StageOutcome::Cancelled {
        remove_created(shared, created).await;
    }
    outcome
}

/// Removes the objects a cancelled run created: no manifest will list them, and a retry writes
/// them again. Objects it found already there (another run's) stay.
async fn remove_created(shared: &Shared, created: &[String]) {
    let mut removed = 0usize;
    for key in created {
        match shared.artifacts.delete(key).await {
            Ok(()) => removed += 1,
            Err(e) => warn!(%key, error = %e, "an object of the cancelled run was not removed"),
        }
    }
    if removed > 0 {
        info!(
            objects = removed,
            "removed the objects the cancelled run wrote"
        );
    }
}

fn fenced_or_lost(e: &QueueError) -> StageOutcome {
    if matches!(e, QueueError::Cancelled { .. }) {
        StageOutcome::Cancelled
    } else {
        if e.kind() != QueueErrorKind::Fenced {
            warn!(error = %e, "could not record the run's end; lease recovery will retry it");
        }
        StageOutcome::LeaseLost
    }
}

/// Retries `op` while the database is unavailable, for up to a lease (after that the run is
/// recovered elsewhere anyway). Other errors return at once.
async fn retry_db<T, F, Fut>(shared: &Shared, what: &str, mut op: F) -> QueueResult<T>
where
    F: FnMut() -> Fut,
    Fut: std::future::Future<Output = QueueResult<T>>,
{
    let give_up = Instant::now() + shared.config.lease;
    let mut pause = Duration::from_millis(100);
    loop {
        match op().await {
            Err(e) if e.kind() == QueueErrorKind::Unavailable && Instant::now() < give_up => {
                warn!(error = %e, "cannot {what}; retrying in {} ms", pause.as_millis());
                tokio::time::sleep(pause).await;
                pause = (pause * 2).min(Duration::from_secs(2));
            }
            other => return other,
        }
    }
}
