//! The work a tenant is waiting on: the open or dead-lettered stage runs of its running or dead
//! jobs (with, for a dead job, the runs its dead stage blocks), newest jobs first (the
//! dashboard's "running" and "dead letters" tables), and its jobs
//! counted by state. Both read through the `(tenant_id, state, id)` index of `jobs`, so their
//! cost follows the page and the tenant's job count, not the size of the whole queue.

use std::collections::BTreeMap;

use super::QueueStore;
use crate::db::{DbRow, Sql, args};
use crate::{
    AssetId, ErrorRecord, JobId, JobState, QueueResult, StageRunId, StageState, TenantId, WorkerId,
};

/// One stage run that is waiting, running or dead, with its job.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkItem {
    /// The job.
    pub job_id: JobId,
    /// Its asset.
    pub asset_id: AssetId,
    /// Where the asset's source is (object-store key).
    pub source_uri: String,
    /// The run.
    pub run_id: StageRunId,
    /// Its stage.
    pub stage_name: String,
    /// `ready`, `running` or `dead`; `blocked` behind a dead stage of a dead job.
    pub state: StageState,
    /// Claims so far.
    pub attempt: u32,
    /// Attempts allowed.
    pub max_attempts: u32,
    /// The worker of the current or last attempt.
    pub worker_id: Option<WorkerId>,
    /// Last claimed, Unix milliseconds.
    pub started_at_ms: Option<i64>,
    /// Not claimable before this, Unix milliseconds.
    pub run_after_ms: i64,
    /// Every failed attempt, oldest first.
    pub errors: Vec<ErrorRecord>,
}

static WORK: Sql = Sql::new(
    "SELECT j.id AS job_id, j.asset_id, a.source_uri, r.id AS run_id, r.stage_name, r.state,
            r.attempt, r.max_attempts, r.worker_id, r.started_at_ms, r.run_after_ms, r.errors
     FROM (SELECT id, asset_id FROM jobs
           WHERE tenant_id = $1 AND state = $2 AND ($3 IS NULL OR id < $3)
           ORDER BY id DESC LIMIT $4) j
     JOIN assets a ON a.id = j.asset_id
     JOIN stage_runs r ON r.job_id = j.id
     WHERE r.state IN ('ready', 'running', 'dead') OR (r.state = 'blocked' AND $2 = 'dead')
     ORDER BY j.id DESC, r.id",
);

static JOB_STATES: Sql = Sql::new(
    "SELECT state, CAST(count(*) AS BIGINT) AS n FROM jobs WHERE tenant_id = $1 GROUP BY state",
);

/// Largest page of [`QueueStore::list_work`], in jobs.
const MAX_JOBS: u32 = 200;

impl QueueStore {
    /// The ready, running and dead stage runs of the tenant's newest `limit` jobs (capped at 200)
    /// in `state` older than `before`, newest job first, then in stage order; for dead jobs also
    /// their blocked runs (what the dead stage holds up).
    pub async fn list_work(
        &self,
        tenant: TenantId,
        state: JobState,
        before: Option<JobId>,
        limit: u32,
    ) -> QueueResult<Vec<WorkItem>> {
        let mut session = self.db.read().await?;
        let rows = session
            .fetch_all(
                &WORK,
                args![
                    tenant.0,
                    state.as_str(),
                    before.map(|j| j.0),
                    i64::from(limit.clamp(1, MAX_JOBS))
                ],
            )
            .await?;
        rows.iter().map(work_item).collect()
    }

    /// How many of the tenant's jobs are in each state.
    pub async fn tenant_job_states(
        &self,
        tenant: TenantId,
    ) -> QueueResult<BTreeMap<JobState, u64>> {
        let mut session = self.db.read().await?;
        job_state_counts(&session.fetch_all(&JOB_STATES, args![tenant.0]).await?)
    }
}

/// Rows of `state, n` (jobs counted by state) as a map.
pub(super) fn job_state_counts(rows: &[DbRow]) -> QueueResult<BTreeMap<JobState, u64>> {
    rows.iter()
        .map(|row| Ok((JobState::parse(&row.text("state")?)?, row.u64("n")?)))
        .collect()
}

fn work_item(row: &DbRow) -> QueueResult<WorkItem> {
    Ok(WorkItem {
        job_id: JobId(row.i64("job_id")?),
        asset_id: AssetId(row.i64("asset_id")?),
        source_uri: row.text("source_uri")?,
        run_id: StageRunId(row.i64("run_id")?),
        stage_name: row.text("stage_name")?,
        state: StageState::parse(&row.text("state")?)?,
        attempt: row.u32("attempt")?,
        max_attempts: row.u32("max_attempts")?,
        worker_id: row.opt_text("worker_id")?.map(WorkerId),
        started_at_ms: row.opt_i64("started_at_ms")?,
        run_after_ms: row.i64("run_after_ms")?,
        errors: row.json("errors")?,
    })
}
