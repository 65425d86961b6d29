//! Operator controls: cancel a job, retry a dead-lettered or cancelled job, pause and resume a
//! stage.

use serde_json::json;

use super::events::{self, EventSubject};
use super::{QueueStore, fencing};
use crate::db::{Sql, args};
use crate::{JobId, JobState, QueueError, QueueResult, StageRunId, TenantId};

/// A stage run named by id and stage (for wake-up hints).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct RunRef {
    /// The run.
    pub run_id: StageRunId,
    /// Its stage.
    pub stage_name: String,
}

static CANCEL_RUNS: Sql = Sql::new(
    "UPDATE stage_runs
     SET state = 'cancelled', finished_at_ms = {now}, lease_expires_at_ms = NULL
     WHERE job_id = $1 AND state IN ('blocked', 'ready', 'running')",
);

static CANCEL_JOB: Sql =
    Sql::new("UPDATE jobs SET state = 'cancelled', finished_at_ms = {now} WHERE id = $1");

// The attempt counter is never reset (it is the fencing token): a retry grants a fresh budget.
// Dead runs and runs stopped by a cancel run again; a cancelled run still waiting on a
// dependency waits again (its count of unfinished dependencies was kept).
static REQUEUE: Sql = Sql::new(
    "UPDATE stage_runs
     SET state = CASE WHEN blocking_deps > 0 THEN 'blocked' ELSE 'ready' END,
         run_after_ms = {now}, finished_at_ms = NULL, lease_expires_at_ms = NULL,
         max_attempts = attempt + attempts_per_retry
     WHERE job_id = $1 AND state IN ('dead', 'cancelled')
     RETURNING id, stage_name, state",
);

static REVIVE_JOB: Sql =
    Sql::new("UPDATE jobs SET state = 'running', finished_at_ms = NULL WHERE id = $1");

static PAUSE: Sql = Sql::new(
    "INSERT INTO paused_stages (stage_name, paused_at_ms) VALUES ($1, {now})
     ON CONFLICT (stage_name) DO NOTHING",
);
static RESUME: Sql = Sql::new("DELETE FROM paused_stages WHERE stage_name = $1");
static PAUSED: Sql = Sql::new("SELECT stage_name FROM paused_stages ORDER BY stage_name");

impl QueueStore {
    /// Cancels a running or dead job of `tenant`: its unfinished runs become cancelled, and a
    /// worker holding one gets `Cancelled` at its next heartbeat or completion. Returns how many
    /// runs were cancelled. A succeeded or cancelled job cannot be cancelled (`InvalidTransition`).
    pub async fn cancel_job(&self, tenant: TenantId, job: JobId) -> QueueResult<u64> {
        let mut tx = self.db.write_tx().await?;
        let state = fencing::lock_tenant_job(&mut tx, tenant, job).await?;
        if !matches!(state, JobState::Running | JobState::Dead) {
            return Err(QueueError::InvalidTransition {
                action: "cancel",
                id: job.to_string(),
                state: state.to_string(),
            });
        }
        let cancelled = tx.execute(&CANCEL_RUNS, args![job.0]).await?;
        tx.execute(&CANCEL_JOB, args![job.0]).await?;
        let detail = json!({ "runs_cancelled": cancelled });
        events::record(
            &mut tx,
            &EventSubject::job(job),
            "job_cancelled",
            Some(detail),
        )
        .await?;
        tx.commit().await?;
        Ok(cancelled)
    }

    /// Retries a dead or cancelled job of `tenant`: its dead-lettered runs, and the runs a cancel
    /// stopped, become claimable now with a fresh attempt budget (their error history is kept;
    /// a run still waiting on an unfinished dependency waits again) and the job runs again.
    /// Returns the runs made claimable. A running or succeeded job cannot be retried
    /// (`InvalidTransition`).
    pub async fn retry_job(&self, tenant: TenantId, job: JobId) -> QueueResult<Vec<RunRef>> {
        let mut tx = self.db.write_tx().await?;
        let state = fencing::lock_tenant_job(&mut tx, tenant, job).await?;
        if !matches!(state, JobState::Dead | JobState::Cancelled) {
            return Err(QueueError::InvalidTransition {
                action: "retry",
                id: job.to_string(),
                state: state.to_string(),
            });
        }
        let mut requeued = Vec::new();
        for row in tx.fetch_all(&REQUEUE, args![job.0]).await? {
            if row.text("state")? != "ready" {
                continue;
            }
            requeued.push(RunRef {
                run_id: StageRunId(row.i64("id")?),
                stage_name: row.text("stage_name")?,
            });
        }
        requeued.sort();
        tx.execute(&REVIVE_JOB, args![job.0]).await?;
        let detail = json!({
            "from": state.to_string(),
            "requeued": requeued.iter().map(|r| &r.stage_name).collect::<Vec<_>>(),
        });
        events::record(
            &mut tx,
            &EventSubject::job(job),
            "job_retried",
            Some(detail),
        )
        .await?;
        tx.commit().await?;
        Ok(requeued)
    }

    /// Stops claims of `stage` (running runs finish); returns false if it was already paused.
    pub async fn pause_stage(&self, stage: &str) -> QueueResult<bool> {
        let mut session = self.db.write_one().await?;
        Ok(session.execute(&PAUSE, args![stage]).await? > 0)
    }

    /// Lets `stage` be claimed again; returns false if it was not paused.
    pub async fn resume_stage(&self, stage: &str) -> QueueResult<bool> {
        let mut session = self.db.write_one().await?;
        Ok(session.execute(&RESUME, args![stage]).await? > 0)
    }

    /// Returns the paused stage names, sorted.
    pub async fn paused_stages(&self) -> QueueResult<Vec<String>> {
        let mut session = self.db.read().await?;
        let rows = session.fetch_all(&PAUSED, args![]).await?;
        rows.iter().map(|r| r.text("stage_name")).collect()
    }
}
