//! Failing a stage run: retry after a backoff while attempts remain, else dead-letter it with its
//! error history; and recovering runs whose lease expired (their worker died) the same way.

use serde::{Deserialize, Serialize};
use serde_json::json;

use super::claim::millis;
use super::events::{self, EventSubject};
use super::{QueueStore, fencing};
use crate::db::{Session, Sql, args};
use crate::{JobState, Lease, QueueError, QueueResult, StageRunId, StageState};

/// Longest error message kept in the history, in bytes; longer ones are cut.
const MAX_MESSAGE_BYTES: usize = 4000;

/// Why an attempt failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// May succeed later (timeout, 5xx, rate limit): retried after a backoff.
    Transient,
    /// Will fail again (bad input): dead-lettered at once.
    Permanent,
    /// The worker stopped heartbeating (crash, kill, partition); recorded by recovery.
    LeaseExpired,
}

/// A failure reported by the worker holding the lease.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StageFailure {
    /// Transient or permanent.
    pub kind: FailureKind,
    /// What happened, for people.
    pub message: String,
}

impl StageFailure {
    /// A failure worth retrying.
    #[must_use]
    pub fn transient(message: impl Into<String>) -> Self {
        Self {
            kind: FailureKind::Transient,
            message: message.into(),
        }
    }

    /// A failure not worth retrying.
    #[must_use]
    pub fn permanent(message: impl Into<String>) -> Self {
        Self {
            kind: FailureKind::Permanent,
            message: message.into(),
        }
    }
}

/// One entry of a run's error history (kept through retries and dead-lettering).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ErrorRecord {
    /// The attempt that failed.
    pub attempt: u32,
    /// Why.
    pub kind: FailureKind,
    /// What happened.
    pub message: String,
    /// The worker that held the attempt.
    pub worker_id: Option<String>,
    /// When it was recorded, Unix milliseconds (database clock).
    pub at_ms: i64,
}

/// What became of a failed run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FailOutcome {
    /// Claimable again from `run_after_ms` (Unix ms, database clock).
    RetryScheduled {
        /// End of the backoff.
        run_after_ms: i64,
    },
    /// Attempts used up or a permanent failure: dead-lettered, and its job is dead.
    DeadLettered,
}

/// What one pass of lease recovery did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecoveryReport {
    /// Runs put back to ready (after a backoff).
    pub requeued: u32,
    /// Runs that had used up their attempts and were dead-lettered (crash loops end here).
    pub dead_lettered: u32,
}

/// Who asks for the failure: the lease holder, or the reaper (which acts only on an expired lease,
/// so a heartbeat that got in first wins).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Caller {
    Holder,
    Reaper,
}

static FENCED_RUN: Sql = Sql::new(
    "SELECT stage_name, max_attempts, errors, worker_id, lease_expires_at_ms, {now} AS now_ms
     FROM stage_runs WHERE id = $1 AND attempt = $2 AND state = 'running' {for_update}",
);

static SET_FAILED: Sql = Sql::new(
    "UPDATE stage_runs
     SET state = $2, errors = $3, run_after_ms = $4, finished_at_ms = $5,
         lease_expires_at_ms = NULL
     WHERE id = $1",
);

static KILL_JOB: Sql = Sql::new(
    "UPDATE jobs SET state = 'dead', finished_at_ms = {now} WHERE id = $1 AND state = 'running'",
);

static EXPIRED: Sql = Sql::new(
    "SELECT id, attempt FROM stage_runs
     WHERE state = 'running' AND lease_expires_at_ms < {now}
     ORDER BY lease_expires_at_ms LIMIT $1",
);

impl QueueStore {
    /// Records a failed attempt of the held run. Transient failures are retried after the
    /// store's backoff until `max_attempts` is used up; permanent ones and the last attempt are
    /// dead-lettered, which also marks the job dead. Fails with `LeaseLost` or `Cancelled`
    /// (changing nothing) if the lease is no longer current.
    pub async fn fail(&self, lease: &Lease, failure: &StageFailure) -> QueueResult<FailOutcome> {
        let mut tx = self.db.write_tx().await?;
        let outcome = self
            .fail_in(&mut tx, lease, failure, Caller::Holder)
            .await?;
        tx.commit().await?;
        outcome.ok_or_else(|| QueueError::CorruptRow("holder failure without outcome".into()))
    }

    /// Finds up to `limit` running runs whose lease has expired and treats each as a failed
    /// attempt ([`FailureKind::LeaseExpired`]): back to ready after a backoff, or dead-lettered
    /// when its attempts are used up. Run it every fraction of the lease so a dead worker's runs
    /// are recovered within about twice the lease.
    pub async fn recover_expired_leases(&self, limit: u32) -> QueueResult<RecoveryReport> {
        let expired = {
            let mut session = self.db.read().await?;
            session.fetch_all(&EXPIRED, args![i64::from(limit)]).await?
        };
        let mut report = RecoveryReport::default();
        let failure = StageFailure {
            kind: FailureKind::LeaseExpired,
            message: "lease expired without heartbeat".into(),
        };
        for row in &expired {
            let lease = Lease {
                run_id: StageRunId(row.i64("id")?),
                attempt: row.u32("attempt")?,
            };
            let mut tx = self.db.write_tx().await?;
            let outcome = match self
                .fail_in(&mut tx, &lease, &failure, Caller::Reaper)
                .await
            {
                Ok(outcome) => outcome,
                // Completed, failed or cancelled since the scan: nothing to recover.
                Err(e) if e.kind() == crate::QueueErrorKind::Fenced => None,
                Err(QueueError::NotFound { .. }) => None,
                Err(e) => return Err(e),
            };
            tx.commit().await?;
            match outcome {
                Some(FailOutcome::RetryScheduled { .. }) => report.requeued += 1,
                Some(FailOutcome::DeadLettered) => report.dead_lettered += 1,
                None => {}
            }
        }
        Ok(report)
    }

    /// The failure transition inside `tx`; `None` when the reaper finds the lease renewed.
    async fn fail_in(
        &self,
        tx: &mut Session,
        lease: &Lease,
        failure: &StageFailure,
        caller: Caller,
    ) -> QueueResult<Option<FailOutcome>> {
        let (job, _) = fencing::lock_job_of_run(tx, lease.run_id).await?;
        let Some(run) = tx
            .fetch_optional(&FENCED_RUN, args![lease.run_id.0, i64::from(lease.attempt)])
            .await?
        else {
            return Err(fencing::lease_error(tx, lease).await);
        };
        let now_ms = run.i64("now_ms")?;
        if caller == Caller::Reaper
            && run
                .opt_i64("lease_expires_at_ms")?
                .is_some_and(|t| t >= now_ms)
        {
            return Ok(None);
        }
        let stage_name = run.text("stage_name")?;
        let mut errors: Vec<ErrorRecord> = run.json("errors")?;
        errors.push(ErrorRecord {
            attempt: lease.attempt,
            kind: failure.kind,
            message: truncate(&failure.message, MAX_MESSAGE_BYTES),
            worker_id: run.opt_text("worker_id")?,
            at_ms: now_ms,
        });
        let dead =
            failure.kind == FailureKind::Permanent || lease.attempt >= run.u32("max_attempts")?;
        let (state, run_after_ms, finished_at_ms) = if dead {
            (StageState::Dead, now_ms, Some(now_ms))
        } else {
            let delay = millis(self.retry.delay(lease.attempt));
            (StageState::Ready, now_ms.saturating_add(delay), None)
        };
        let errors_json =
            serde_json::to_value(&errors).map_err(|e| QueueError::CorruptRow(e.to_string()))?;
        tx.execute(
            &SET_FAILED,
            args![
                lease.run_id.0,
                state.as_str(),
                errors_json,
                run_after_ms,
                finished_at_ms
            ],
        )
        .await?;

        let subject = EventSubject {
            job,
            run: Some((lease.run_id, &stage_name)),
            attempt: Some(lease.attempt),
        };
        let detail = json!({ "kind": failure.kind, "message": errors.last().map(|e| &e.message) });
        if dead {
            events::record(tx, &subject, "stage_dead", Some(detail)).await?;
            if tx.execute(&KILL_JOB, args![job.0]).await? > 0 {
                let kind = format!("job_{}", JobState::Dead);
                events::record(tx, &EventSubject::job(job), &kind, None).await?;
            }
            Ok(Some(FailOutcome::DeadLettered))
        } else {
            events::record(tx, &subject, "stage_failed", Some(detail)).await?;
            Ok(Some(FailOutcome::RetryScheduled { run_after_ms }))
        }
    }
}

fn truncate(message: &str, max_bytes: usize) -> String {
    if message.len() <= max_bytes {
        return message.to_owned();
    }
    let mut end = max_bytes;
    while !message.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}…", &message[..end])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_messages_are_cut_on_a_char_boundary() {
        assert_eq!(truncate("abc", 3), "abc");
        assert_eq!(truncate("abcd", 3), "abc…");
        assert_eq!(truncate("ééé", 3), "é…");
    }
}
