//! Completing a stage run: its output manifest, its cost, the stages it unblocks and, when it
//! was the last, the job, all in one transaction.

use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::events::{self, EventSubject};
use super::{QueueStore, RunRef, fencing};
use crate::db::{Sql, args};
use crate::{JobState, Lease, QueueError, QueueResult, StageRunId};

/// Largest output manifest accepted, in bytes of JSON: manifests name artifacts (object keys and
/// digests), they never carry them.
pub const MAX_MANIFEST_BYTES: usize = 64 * 1024;

/// What a stage run consumed, summed by the worker. Wall time is `finished - started`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageCost {
    /// GPU time, milliseconds.
    pub gpu_ms: u64,
    /// Requests to the LVLM.
    pub lvlm_requests: u64,
    /// Tokens in and out of the LVLM.
    pub lvlm_tokens: u64,
    /// Money spent on external services, millionths of a US dollar.
    pub usd_micros: u64,
}

/// What completing a run changed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompleteOutcome {
    /// Downstream runs that became claimable, by id (wake their stages' workers).
    pub unblocked: Vec<RunRef>,
    /// Whether this was the job's last stage and the job succeeded.
    pub job_succeeded: bool,
}

static SUCCEED: Sql = Sql::new(
    "UPDATE stage_runs
     SET state = 'succeeded', output_manifest = $3, cost = $4, finished_at_ms = {now},
         lease_expires_at_ms = NULL
     WHERE id = $1 AND attempt = $2 AND state = 'running'
     RETURNING stage_name",
);

// A dependent becomes ready when its last blocking dependency succeeds (SET reads old values).
static UNBLOCK: Sql = Sql::new(
    "UPDATE stage_runs
     SET blocking_deps = blocking_deps - 1,
         state = CASE WHEN blocking_deps = 1 AND state = 'blocked' THEN 'ready' ELSE state END,
         run_after_ms = CASE WHEN blocking_deps = 1 AND state = 'blocked' THEN {now} ELSE run_after_ms END
     WHERE id IN (SELECT stage_run_id FROM stage_deps WHERE depends_on_id = $1)
     RETURNING id, stage_name, state",
);

static FINISH_JOB: Sql = Sql::new(
    "UPDATE jobs SET state = 'succeeded', finished_at_ms = {now}
     WHERE id = $1 AND state = 'running'
       AND NOT EXISTS (SELECT 1 FROM stage_runs WHERE job_id = $1 AND state <> 'succeeded')",
);

impl QueueStore {
    /// Marks the held run succeeded with its output manifest and cost, makes the stages that
    /// waited only for it claimable and, if it was the last, marks the job succeeded: one
    /// transaction, so a crash leaves either all of it or none. Fails with `LeaseLost` or
    /// `Cancelled` (changing nothing) if the lease is no longer current.
    pub async fn complete(
        &self,
        lease: &Lease,
        output_manifest: &Value,
        cost: &StageCost,
    ) -> QueueResult<CompleteOutcome> {
        let manifest_bytes = output_manifest.to_string().len();
        if manifest_bytes > MAX_MANIFEST_BYTES {
            return Err(QueueError::Invalid(format!(
                "output manifest of {manifest_bytes} bytes exceeds {MAX_MANIFEST_BYTES}: store artifacts, not data"
            )));
        }
        let mut tx = self.db.write_tx().await?;
        let (job, _) = fencing::lock_job_of_run(&mut tx, lease.run_id).await?;
        let cost_json =
            serde_json::to_value(cost).map_err(|e| QueueError::Invalid(e.to_string()))?;
        let Some(row) = tx
            .fetch_optional(
                &SUCCEED,
                args![
                    lease.run_id.0,
                    i64::from(lease.attempt),
                    output_manifest.clone(),
                    cost_json
                ],
            )
            .await?
        else {
            return Err(fencing::lease_error(&mut tx, lease).await);
        };
        let stage_name = row.text("stage_name")?;

        let mut unblocked = Vec::new();
        for row in tx.fetch_all(&UNBLOCK, args![lease.run_id.0]).await? {
            if row.text("state")? == "ready" {
                unblocked.push(RunRef {
                    run_id: StageRunId(row.i64("id")?),
                    stage_name: row.text("stage_name")?,
                });
            }
        }
        unblocked.sort_by_key(|r| r.run_id);
        let job_succeeded = tx.execute(&FINISH_JOB, args![job.0]).await? > 0;

        let subject = EventSubject {
            job,
            run: Some((lease.run_id, &stage_name)),
            attempt: Some(lease.attempt),
        };
        let detail =
            json!({ "unblocked": unblocked.iter().map(|r| &r.stage_name).collect::<Vec<_>>() });
        events::record(&mut tx, &subject, "stage_succeeded", Some(detail)).await?;
        if job_succeeded {
            let kind = format!("job_{}", JobState::Succeeded);
            events::record(&mut tx, &EventSubject::job(job), &kind, None).await?;
        }
        tx.commit().await?;
        Ok(CompleteOutcome {
            unblocked,
            job_succeeded,
        })
    }
}
