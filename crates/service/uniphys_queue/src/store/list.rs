//! Listing a tenant's jobs, newest first, with filters and keyset pagination.

use super::QueueStore;
use crate::db::{DbRow, Sql, args};
use crate::{AssetId, JobId, JobState, QueueError, QueueResult, TenantId};

/// Which jobs to list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JobFilter {
    /// Only jobs in this state.
    pub state: Option<JobState>,
    /// Only jobs of this asset.
    pub asset: Option<AssetId>,
    /// Only jobs in this batch of the tenant.
    pub batch: Option<String>,
    /// Only jobs older than this one (the last id of the previous page).
    pub before: Option<JobId>,
    /// Page size (at most 1000).
    pub limit: u32,
}

impl Default for JobFilter {
    /// All jobs, the 100 newest.
    fn default() -> Self {
        Self {
            state: None,
            asset: None,
            batch: None,
            before: None,
            limit: 100,
        }
    }
}

/// One job in a listing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JobSummary {
    /// The job.
    pub id: JobId,
    /// Its asset.
    pub asset_id: AssetId,
    /// Where the asset's source is (object-store key).
    pub source_uri: String,
    /// Where it is.
    pub state: JobState,
    /// Its priority.
    pub priority: i32,
    /// Created, Unix milliseconds (database clock).
    pub created_at_ms: i64,
    /// Finished, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
}

static LIST: Sql = Sql::new(
    "SELECT j.id, j.asset_id, a.source_uri, j.state, j.priority, j.created_at_ms, j.finished_at_ms
     FROM jobs j JOIN assets a ON a.id = j.asset_id
     WHERE j.tenant_id = $1
       AND ($2 IS NULL OR j.state = $2)
       AND ($3 IS NULL OR j.asset_id = $3)
       AND ($4 IS NULL OR j.id < $4)
       AND ($6 IS NULL OR EXISTS (SELECT 1 FROM batch_items b
                                  WHERE b.tenant_id = j.tenant_id AND b.batch = $6 AND b.job_id = j.id))
     ORDER BY j.id DESC
     LIMIT $5",
);

/// Largest page [`QueueStore::list_jobs`] returns.
const MAX_PAGE: u32 = 1000;

impl QueueStore {
    /// Returns the jobs of `tenant` matching `filter`, newest first (sorted by id, descending).
    pub async fn list_jobs(
        &self,
        tenant: TenantId,
        filter: &JobFilter,
    ) -> QueueResult<Vec<JobSummary>> {
        let mut session = self.db.read().await?;
        let rows = session
            .fetch_all(
                &LIST,
                args![
                    tenant.0,
                    filter.state.map(|s| s.as_str().to_owned()),
                    filter.asset.map(|a| a.0),
                    filter.before.map(|j| j.0),
                    i64::from(filter.limit.min(MAX_PAGE)),
                    filter.batch.clone(),
                ],
            )
            .await?;
        rows.iter().map(summary).collect()
    }
}

fn summary(row: &DbRow) -> QueueResult<JobSummary> {
    Ok(JobSummary {
        id: JobId(row.i64("id")?),
        asset_id: AssetId(row.i64("asset_id")?),
        source_uri: row.text("source_uri")?,
        state: JobState::parse(&row.text("state")?)?,
        priority: i32::try_from(row.i64("priority")?)
            .map_err(|_| QueueError::CorruptRow("priority out of range".into()))?,
        created_at_ms: row.i64("created_at_ms")?,
        finished_at_ms: row.opt_i64("finished_at_ms")?,
    })
}
