//! Submitting an asset and creating its job in one transaction; a re-submit of the same content
//! by the same tenant finds the existing asset and job (a unique index, not a lookup, decides).

use std::collections::BTreeMap;

use serde_json::json;

use super::QueueStore;
use super::assets::backlog_in;
use super::batches::{add_to_batch, validate_batch_label};
use super::events::{self, EventSubject};
use crate::db::{Session, Sql, args};
use crate::{AssetId, JobId, JobSpec, QueueError, QueueResult, StageState, TenantId};

/// An asset as submitted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NewAsset {
    /// Digest of the content, e.g. `sha256:<hex>`: the de-duplication key per tenant.
    pub content_digest: String,
    /// Where the content is (object-store key or URL); never the content itself.
    pub source_uri: String,
    /// Size of the content.
    pub size_bytes: u64,
}

/// The result of a submit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Submission {
    /// The asset (new or existing).
    pub asset_id: AssetId,
    /// The job working on it (new, or the asset's latest).
    pub job_id: JobId,
    /// Whether this call created the asset (false: a re-submit of known content).
    pub asset_created: bool,
    /// Whether this call created the job.
    pub job_created: bool,
}

static INSERT_ASSET: Sql = Sql::new(
    "INSERT INTO assets (tenant_id, content_digest, source_uri, size_bytes, created_at_ms)
     VALUES ($1, $2, $3, $4, {now})
     ON CONFLICT (tenant_id, content_digest) DO NOTHING
     RETURNING id",
);
// Serialises a tenant's capped submissions (SQLite's writer is single already).
static LOCK_TENANT: Sql = Sql::new("SELECT id FROM tenants WHERE id = $1 {for_update}");
static FIND_ASSET: Sql =
    Sql::new("SELECT id FROM assets WHERE tenant_id = $1 AND content_digest = $2");
static OWNED_ASSET: Sql = Sql::new("SELECT id FROM assets WHERE id = $1 AND tenant_id = $2");
static LATEST_JOB: Sql =
    Sql::new("SELECT id FROM jobs WHERE asset_id = $1 ORDER BY id DESC LIMIT 1");
static INSERT_JOB: Sql = Sql::new(
    "INSERT INTO jobs (tenant_id, asset_id, state, priority, dag, created_at_ms)
     VALUES ($1, $2, 'running', $3, $4, {now})
     RETURNING id",
);
static INSERT_RUN: Sql = Sql::new(
    "INSERT INTO stage_runs (job_id, tenant_id, asset_id, stage_name, state, blocking_deps,
                             max_attempts, attempts_per_retry, priority, run_after_ms, created_at_ms)
     VALUES ($1, $2, $3, $4, $5, $6, $7, $7, $8, {now}, {now})
     RETURNING id",
);
static INSERT_DEP: Sql =
    Sql::new("INSERT INTO stage_deps (depends_on_id, stage_run_id) VALUES ($1, $2)");

impl QueueStore {
    /// Stores `asset` for `tenant` and creates its job from `spec`, in one transaction. If the
    /// tenant already submitted the same content digest, returns that asset and its latest job
    /// instead (creating a job only if it has none, e.g. after retention removed it).
    pub async fn submit(
        &self,
        tenant: TenantId,
        asset: &NewAsset,
        spec: &JobSpec,
    ) -> QueueResult<Submission> {
        self.submit_in_batch(tenant, asset, spec, None).await
    }

    /// [`submit`](Self::submit), and in the same transaction adds the job (new or existing) to
    /// the tenant's batch labelled `batch` (see [`validate_batch_label`]).
    pub async fn submit_in_batch(
        &self,
        tenant: TenantId,
        asset: &NewAsset,
        spec: &JobSpec,
        batch: Option<&str>,
    ) -> QueueResult<Submission> {
        self.submit_capped(tenant, asset, spec, batch, None).await
    }

    /// [`submit_in_batch`](Self::submit_in_batch) refused with `BacklogFull` when a new job
    /// would take the tenant's unfinished stage runs over `max_backlog`, checked in the
    /// submission's transaction with the tenant's row locked, so concurrent submissions cannot
    /// pass the cap together (a re-submit that creates no job is never refused; nothing is kept
    /// of a refused one).
    pub async fn submit_capped(
        &self,
        tenant: TenantId,
        asset: &NewAsset,
        spec: &JobSpec,
        batch: Option<&str>,
        max_backlog: Option<u64>,
    ) -> QueueResult<Submission> {
        spec.validate()?;
        if let Some(label) = batch {
            validate_batch_label(label)?;
        }
        let size = i64::try_from(asset.size_bytes)
            .map_err(|_| QueueError::Invalid("asset too large".into()))?;
        let mut tx = self.db.write_tx().await?;
        // Known content first: an insert that meets the conflict would still use up an id of
        // PostgreSQL's sequence on every re-submit.
        let known = tx
            .fetch_optional(&FIND_ASSET, args![tenant.0, asset.content_digest.as_str()])
            .await?;
        // New content makes a job: the cap is checked before anything is written (a refused
        // insert would still use up a sequence id).
        if known.is_none()
            && let Some(cap) = max_backlog
        {
            check_cap(&mut tx, tenant, spec, cap).await?;
        }
        let inserted = match known {
            Some(_) => None,
            None => tx
                .fetch_optional(
                    &INSERT_ASSET,
                    args![
                        tenant.0,
                        asset.content_digest.as_str(),
                        asset.source_uri.as_str(),
                        size
                    ],
                )
                .await
                .map_err(|e| foreign_key_to_not_found(e, tenant))?,
        };
        let (asset_id, asset_created) = match (known, inserted) {
            (_, Some(row)) => (AssetId(row.i64("id")?), true),
            (Some(row), None) => (AssetId(row.i64("id")?), false),
            // Inserted by a concurrent submission between the look-up and the insert.
            (None, None) => {
                let row = tx
                    .fetch_one(&FIND_ASSET, args![tenant.0, asset.content_digest.as_str()])
                    .await?;
                (AssetId(row.i64("id")?), false)
            }
        };
        let existing = if asset_created {
            None
        } else {
            tx.fetch_optional(&LATEST_JOB, args![asset_id.0]).await?
        };
        let (job_id, job_created) = match existing {
            Some(row) => (JobId(row.i64("id")?), false),
            None => {
                // Known content without a job (its job was purged): checked here.
                if !asset_created && let Some(cap) = max_backlog {
                    check_cap(&mut tx, tenant, spec, cap).await?;
                }
                (insert_job(&mut tx, tenant, asset_id, spec).await?, true)
            }
        };
        if let Some(label) = batch {
            add_to_batch(&mut tx, tenant, label, job_id).await?;
        }
        tx.commit().await?;
        Ok(Submission {
            asset_id,
            job_id,
            asset_created,
            job_created,
        })
    }

    /// Creates another job from `spec` on an asset of `tenant` (an explicit re-run).
    pub async fn create_job(
        &self,
        tenant: TenantId,
        asset: AssetId,
        spec: &JobSpec,
    ) -> QueueResult<JobId> {
        spec.validate()?;
        let mut tx = self.db.write_tx().await?;
        if tx
            .fetch_optional(&OWNED_ASSET, args![asset.0, tenant.0])
            .await?
            .is_none()
        {
            return Err(QueueError::not_found("asset", asset));
        }
        let job = insert_job(&mut tx, tenant, asset, spec).await?;
        tx.commit().await?;
        Ok(job)
    }
}

/// Refuses with `BacklogFull` when `spec`'s runs would take `tenant`'s unfinished stage runs
/// over `cap`; the tenant's row stays locked until the transaction ends, so concurrent capped
/// submissions of one tenant are counted one after another.
async fn check_cap(
    tx: &mut Session,
    tenant: TenantId,
    spec: &JobSpec,
    cap: u64,
) -> QueueResult<()> {
    tx.fetch_optional(&LOCK_TENANT, args![tenant.0]).await?;
    let backlog = backlog_in(tx, tenant).await?;
    let adding = spec.stages.len() as u64;
    if backlog.saturating_add(adding) > cap {
        return Err(QueueError::BacklogFull {
            backlog,
            adding,
            cap,
        });
    }
    Ok(())
}

/// Inserts the job, its runs (dependencies first) and the DAG edges.
async fn insert_job(
    tx: &mut Session,
    tenant: TenantId,
    asset: AssetId,
    spec: &JobSpec,
) -> QueueResult<JobId> {
    let dag = serde_json::to_value(spec).map_err(|e| QueueError::Invalid(e.to_string()))?;
    let row = tx
        .fetch_one(
            &INSERT_JOB,
            args![tenant.0, asset.0, i64::from(spec.priority), dag],
        )
        .await?;
    let job = JobId(row.i64("id")?);
    let mut run_ids: BTreeMap<&str, i64> = BTreeMap::new();
    for name in spec.topological_order() {
        let Some(stage) = spec.stages.iter().find(|s| s.name == name) else {
            continue;
        };
        let state = if stage.depends_on.is_empty() {
            StageState::Ready
        } else {
            StageState::Blocked
        };
        let blocking = i64::try_from(stage.depends_on.len()).unwrap_or(i64::MAX);
        let row = tx
            .fetch_one(
                &INSERT_RUN,
                args![
                    job.0,
                    tenant.0,
                    asset.0,
                    name,
                    state.as_str(),
                    blocking,
                    i64::from(stage.max_attempts),
                    i64::from(spec.priority),
                ],
            )
            .await?;
        let run = row.i64("id")?;
        for dep in &stage.depends_on {
            let upstream = *run_ids.get(dep.as_str()).ok_or_else(|| {
                QueueError::Invalid(format!("stage {name} depends on unknown {dep}"))
            })?;
            tx.execute(&INSERT_DEP, args![upstream, run]).await?;
        }
        run_ids.insert(name, run);
    }
    let detail = json!({ "asset_id": asset.0, "stages": run_ids.len() });
    events::record(tx, &EventSubject::job(job), "job_created", Some(detail)).await?;
    Ok(job)
}

fn foreign_key_to_not_found(e: QueueError, tenant: TenantId) -> QueueError {
    match &e {
        QueueError::Database(sqlx::Error::Database(db)) if db.is_foreign_key_violation() => {
            QueueError::not_found("tenant", tenant)
        }
        _ => e,
    }
}
