//! Claiming runnable stage runs and renewing their leases.

use std::time::Duration;

use super::{QueueStore, fencing};
use crate::db::{DbRow, Sql, args};
use crate::{AssetId, JobId, QueueResult, StageRunId, TenantId, WorkerId};

/// The fencing token of one claimed attempt. Heartbeat, complete and fail name it; once the run
/// has moved on (recovered, reclaimed, cancelled), they fail with `LeaseLost` or `Cancelled`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Lease {
    /// The stage run.
    pub run_id: StageRunId,
    /// The attempt this claim started (1 for the first claim; never reused).
    pub attempt: u32,
}

/// A stage run a worker now holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClaimedRun {
    /// The fencing token to pass back.
    pub lease: Lease,
    /// Its job.
    pub job_id: JobId,
    /// The job's tenant.
    pub tenant_id: TenantId,
    /// The asset the job runs on.
    pub asset_id: AssetId,
    /// The stage to run.
    pub stage_name: String,
    /// The attempt at which the run is dead-lettered if it fails.
    pub max_attempts: u32,
    /// When the lease ends unless renewed, Unix milliseconds (database clock).
    pub lease_expires_at_ms: i64,
}

// Ready, due and not paused; highest priority first, then the oldest run (lowest id: runs are
// made with their job, so a run put back after a crash or a backoff goes before work submitted
// after it, not behind the whole backlog). The attempt is counted here, so a run that kills its worker still uses up
// attempts. The pick is a materialized CTE: as an `IN (subquery)` Postgres may re-run it per row
// and claim past the limit.
//
// Postgres: one ordered scan of the claim index per requested stage (LATERAL, LIMIT), skipping rows
// other claimers hold, then the best of those; cost does not grow with the backlog (a plain
// `stage_name = ANY(..) ORDER BY ..` sorts every ready row of those stages). The few extra rows a
// per-stage scan locks are released when the statement commits.
// SQLite: the same order with `IN`; it has a single writer, so nothing to skip.
static CLAIM: Sql = Sql::per_dialect(
    "WITH picked AS MATERIALIZED (
         SELECT c.id FROM unnest(CAST($1 AS TEXT[])) AS s(name)
         CROSS JOIN LATERAL (
             SELECT id, priority FROM stage_runs
             WHERE state = 'ready' AND stage_name = s.name AND run_after_ms <= {now}
             ORDER BY priority DESC, id
             LIMIT $2
             FOR UPDATE SKIP LOCKED) AS c
         WHERE s.name NOT IN (SELECT stage_name FROM paused_stages)
         ORDER BY c.priority DESC, c.id
         LIMIT $2)
     UPDATE stage_runs
     SET state = 'running', attempt = attempt + 1, worker_id = $3,
         lease_expires_at_ms = {now} + $4, started_at_ms = {now}
     WHERE state = 'ready' AND id IN (SELECT id FROM picked)
     RETURNING id, job_id, tenant_id, asset_id, stage_name, attempt, max_attempts,
               lease_expires_at_ms, priority",
    "WITH picked AS MATERIALIZED (
         SELECT id FROM stage_runs
         WHERE state = 'ready' AND stage_name {in_list_1} AND run_after_ms <= {now}
           AND stage_name NOT IN (SELECT stage_name FROM paused_stages)
         ORDER BY priority DESC, id
         LIMIT $2)
     UPDATE stage_runs
     SET state = 'running', attempt = attempt + 1, worker_id = $3,
         lease_expires_at_ms = {now} + $4, started_at_ms = {now}
     WHERE state = 'ready' AND id IN (SELECT id FROM picked)
     RETURNING id, job_id, tenant_id, asset_id, stage_name, attempt, max_attempts,
               lease_expires_at_ms, priority",
);

static HEARTBEAT: Sql = Sql::new(
    "UPDATE stage_runs SET lease_expires_at_ms = {now} + $3
     WHERE id = $1 AND attempt = $2 AND state = 'running'
     RETURNING lease_expires_at_ms",
);

pub(super) fn millis(duration: Duration) -> i64 {
    i64::try_from(duration.as_millis()).unwrap_or(i64::MAX)
}

impl QueueStore {
    /// Claims up to `limit` runnable stage runs of the named stages for `worker`, each leased for
    /// `lease`. Returns them in claim order (priority, then the run's age); empty when nothing
    /// is due.
    /// Runs of paused stages and retries still in their backoff are not claimed.
    pub async fn claim(
        &self,
        worker: &WorkerId,
        stages: &[&str],
        lease: Duration,
        limit: u32,
    ) -> QueueResult<Vec<ClaimedRun>> {
        if stages.is_empty() || limit == 0 {
            return Ok(Vec::new());
        }
        let names: Vec<String> = stages.iter().map(|s| (*s).to_owned()).collect();
        let mut session = self.db.write_one().await?;
        let rows = session
            .fetch_all(
                &CLAIM,
                args![names, i64::from(limit), worker.0.as_str(), millis(lease)],
            )
            .await?;
        let mut claimed = Vec::with_capacity(rows.len());
        for row in &rows {
            claimed.push((claim_order(row)?, claimed_run(row)?));
        }
        claimed.sort_by_key(|(order, _)| *order);
        Ok(claimed.into_iter().map(|(_, run)| run).collect())
    }

    /// Renews the lease of a run this worker holds; returns the new expiry (Unix ms). Call every
    /// third of the lease. A lease that ran out is still renewed if nobody recovered the run yet;
    /// once it was recovered or cancelled this fails with `LeaseLost` or `Cancelled`.
    pub async fn heartbeat(&self, lease: &Lease, extend_by: Duration) -> QueueResult<i64> {
        let mut session = self.db.write_one().await?;
        let row = session
            .fetch_optional(
                &HEARTBEAT,
                args![lease.run_id.0, i64::from(lease.attempt), millis(extend_by)],
            )
            .await?;
        match row {
            Some(row) => row.i64("lease_expires_at_ms"),
            None => Err(fencing::lease_error(&mut session, lease).await),
        }
    }
}

fn claim_order(row: &DbRow) -> QueueResult<(std::cmp::Reverse<i64>, i64)> {
    Ok((std::cmp::Reverse(row.i64("priority")?), row.i64("id")?))
}

fn claimed_run(row: &DbRow) -> QueueResult<ClaimedRun> {
    Ok(ClaimedRun {
        lease: Lease {
            run_id: StageRunId(row.i64("id")?),
            attempt: row.u32("attempt")?,
        },
        job_id: JobId(row.i64("job_id")?),
        tenant_id: TenantId(row.i64("tenant_id")?),
        asset_id: AssetId(row.i64("asset_id")?),
        stage_name: row.text("stage_name")?,
        max_attempts: row.u32("max_attempts")?,
        lease_expires_at_ms: row.i64("lease_expires_at_ms")?,
    })
}
