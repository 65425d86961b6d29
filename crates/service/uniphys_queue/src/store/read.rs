//! Reading a job and its stage runs (status pages, workers fetching upstream outputs).

use serde_json::Value;

use super::QueueStore;
use crate::db::{DbRow, Sql, args};
use crate::{
    AssetId, ErrorRecord, JobId, JobSpec, JobState, QueueError, QueueResult, StageCost, StageRunId,
    StageState, TenantId, WorkerId,
};

/// A job with all its stage runs.
#[derive(Clone, Debug, PartialEq)]
pub struct JobDetail {
    /// The job.
    pub id: JobId,
    /// Its asset.
    pub asset_id: AssetId,
    /// Where it is.
    pub state: JobState,
    /// Its priority.
    pub priority: i32,
    /// The stage graph it was created with.
    pub spec: JobSpec,
    /// Created, Unix milliseconds (database clock).
    pub created_at_ms: i64,
    /// Succeeded, dead-lettered or cancelled, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
    /// Its stage runs, by id (creation order, dependencies first).
    pub stages: Vec<StageRunInfo>,
}

/// One stage run as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct StageRunInfo {
    /// The run.
    pub id: StageRunId,
    /// Its stage.
    pub stage_name: String,
    /// Where it is.
    pub state: StageState,
    /// Claims so far (the current or last attempt).
    pub attempt: u32,
    /// The attempt at which a failure dead-letters it.
    pub max_attempts: u32,
    /// Not claimable before this, Unix milliseconds (the backoff of a retry).
    pub run_after_ms: i64,
    /// The lease end while running.
    pub lease_expires_at_ms: Option<i64>,
    /// The worker of the current or last attempt.
    pub worker_id: Option<WorkerId>,
    /// Every failed attempt, oldest first.
    pub errors: Vec<ErrorRecord>,
    /// What the stage wrote (object keys and digests), once succeeded.
    pub output_manifest: Option<Value>,
    /// What it consumed, once succeeded.
    pub cost: Option<StageCost>,
    /// Last claimed, Unix milliseconds.
    pub started_at_ms: Option<i64>,
    /// Succeeded, dead-lettered or cancelled, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
}

impl JobDetail {
    /// Returns the run of `stage`, if the job has one.
    #[must_use]
    pub fn stage(&self, stage: &str) -> Option<&StageRunInfo> {
        self.stages.iter().find(|s| s.stage_name == stage)
    }
}

static JOB: Sql = Sql::new(
    "SELECT id, asset_id, state, priority, dag, created_at_ms, finished_at_ms
     FROM jobs WHERE id = $1 AND tenant_id = $2",
);

static RUNS: Sql = Sql::new(
    "SELECT id, stage_name, state, attempt, max_attempts, run_after_ms, lease_expires_at_ms,
            worker_id, errors, output_manifest, cost, started_at_ms, finished_at_ms
     FROM stage_runs WHERE job_id = $1 ORDER BY id",
);

static UPSTREAM: Sql = Sql::new(
    "SELECT u.stage_name, u.output_manifest FROM stage_deps d
     JOIN stage_runs u ON u.id = d.depends_on_id
     WHERE d.stage_run_id = $1
     ORDER BY u.stage_name",
);

impl QueueStore {
    /// Returns the output manifests of the stages `run` depends on, by stage name (what a worker
    /// reads before running the stage). A dependency without a manifest has `Value::Null`.
    pub async fn upstream_outputs(&self, run: StageRunId) -> QueueResult<Vec<(String, Value)>> {
        let mut session = self.db.read().await?;
        let rows = session.fetch_all(&UPSTREAM, args![run.0]).await?;
        rows.iter()
            .map(|row| {
                let manifest: Option<Value> = row.opt_json("output_manifest")?;
                Ok((row.text("stage_name")?, manifest.unwrap_or(Value::Null)))
            })
            .collect()
    }

    /// Returns `job` of `tenant` with its stage runs; `NotFound` for another tenant's job.
    pub async fn get_job(&self, tenant: TenantId, job: JobId) -> QueueResult<JobDetail> {
        let mut session = self.db.read().await?;
        let row = session
            .fetch_optional(&JOB, args![job.0, tenant.0])
            .await?
            .ok_or_else(|| QueueError::not_found("job", job))?;
        let runs = session.fetch_all(&RUNS, args![job.0]).await?;
        Ok(JobDetail {
            id: job,
            asset_id: AssetId(row.i64("asset_id")?),
            state: JobState::parse(&row.text("state")?)?,
            priority: i32::try_from(row.i64("priority")?)
                .map_err(|_| QueueError::CorruptRow("priority out of range".into()))?,
            spec: row.json("dag")?,
            created_at_ms: row.i64("created_at_ms")?,
            finished_at_ms: row.opt_i64("finished_at_ms")?,
            stages: runs.iter().map(stage_run).collect::<QueueResult<_>>()?,
        })
    }
}

fn stage_run(row: &DbRow) -> QueueResult<StageRunInfo> {
    Ok(StageRunInfo {
        id: StageRunId(row.i64("id")?),
        stage_name: row.text("stage_name")?,
        state: StageState::parse(&row.text("state")?)?,
        attempt: row.u32("attempt")?,
        max_attempts: row.u32("max_attempts")?,
        run_after_ms: row.i64("run_after_ms")?,
        lease_expires_at_ms: row.opt_i64("lease_expires_at_ms")?,
        worker_id: row.opt_text("worker_id")?.map(WorkerId),
        errors: row.json("errors")?,
        output_manifest: row.opt_json("output_manifest")?,
        cost: row.opt_json("cost")?,
        started_at_ms: row.opt_i64("started_at_ms")?,
        finished_at_ms: row.opt_i64("finished_at_ms")?,
    })
}
