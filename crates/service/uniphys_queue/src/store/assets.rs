//! Reading assets, a tenant's backlog (for backpressure) and what a worker needs to run a stage.

use serde_json::Value;

use super::QueueStore;
use crate::db::{DbRow, Session, Sql, args};
use crate::{AssetId, JobId, JobSpec, QueueError, QueueResult, StageRunId, TenantId};

/// An asset as stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AssetInfo {
    /// The asset.
    pub id: AssetId,
    /// Its owner.
    pub tenant_id: TenantId,
    /// Digest of its content (the de-duplication key per tenant).
    pub content_digest: String,
    /// Where its content is (object-store key).
    pub source_uri: String,
    /// Size of its content.
    pub size_bytes: u64,
    /// Submitted, Unix milliseconds (database clock).
    pub created_at_ms: i64,
}

/// Everything a worker reads before running a claimed stage run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunContext {
    /// The run's job.
    pub job_id: JobId,
    /// The asset it works on.
    pub asset: AssetInfo,
    /// The trace context of the submitting request, if any.
    pub trace_parent: Option<String>,
    /// Output manifests of the stages it depends on, by stage name.
    pub upstream: Vec<(String, Value)>,
}

static ASSET: Sql = Sql::new(
    "SELECT a.id, a.tenant_id, a.content_digest, a.source_uri, a.size_bytes, a.created_at_ms
     FROM assets a WHERE a.id = $1 AND a.tenant_id = $2",
);
static RUN_ASSET: Sql = Sql::new(
    "SELECT a.id, a.tenant_id, a.content_digest, a.source_uri, a.size_bytes, a.created_at_ms,
            j.id AS job_id, j.dag
     FROM stage_runs r JOIN jobs j ON j.id = r.job_id JOIN assets a ON a.id = r.asset_id
     WHERE r.id = $1",
);
static BACKLOG: Sql = Sql::new(
    "SELECT COUNT(*) AS n FROM stage_runs
     WHERE tenant_id = $1 AND state IN ('blocked', 'ready', 'running')",
);

/// Unfinished stage runs of `tenant`, counted in `session` (a submission's transaction too).
pub(super) async fn backlog_in(session: &mut Session, tenant: TenantId) -> QueueResult<u64> {
    let row = session.fetch_one(&BACKLOG, args![tenant.0]).await?;
    u64::try_from(row.i64("n")?).map_err(|_| QueueError::CorruptRow("negative count".into()))
}

fn asset_info(row: &DbRow) -> QueueResult<AssetInfo> {
    Ok(AssetInfo {
        id: AssetId(row.i64("id")?),
        tenant_id: TenantId(row.i64("tenant_id")?),
        content_digest: row.text("content_digest")?,
        source_uri: row.text("source_uri")?,
        size_bytes: u64::try_from(row.i64("size_bytes")?)
            .map_err(|_| QueueError::CorruptRow("negative asset size".into()))?,
        created_at_ms: row.i64("created_at_ms")?,
    })
}

impl QueueStore {
    /// Returns `asset` of `tenant`; `NotFound` for another tenant's asset.
    pub async fn get_asset(&self, tenant: TenantId, asset: AssetId) -> QueueResult<AssetInfo> {
        let mut session = self.db.read().await?;
        let row = session
            .fetch_optional(&ASSET, args![asset.0, tenant.0])
            .await?
            .ok_or_else(|| QueueError::not_found("asset", asset))?;
        asset_info(&row)
    }

    /// Unfinished stage runs (blocked, ready or running) of `tenant`: what an API compares with
    /// its backlog cap before accepting more work.
    pub async fn tenant_backlog(&self, tenant: TenantId) -> QueueResult<u64> {
        let mut session = self.db.read().await?;
        backlog_in(&mut session, tenant).await
    }

    /// Returns what a worker needs to run `run`: its asset, the job's trace context and the
    /// upstream manifests.
    pub async fn run_context(&self, run: StageRunId) -> QueueResult<RunContext> {
        let row = {
            let mut session = self.db.read().await?;
            session
                .fetch_optional(&RUN_ASSET, args![run.0])
                .await?
                .ok_or_else(|| QueueError::not_found("stage run", run))?
        };
        let spec: JobSpec = row.json("dag")?;
        Ok(RunContext {
            job_id: JobId(row.i64("job_id")?),
            asset: asset_info(&row)?,
            trace_parent: spec.trace_parent,
            upstream: self.upstream_outputs(run).await?,
        })
    }
}
