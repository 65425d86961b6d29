//! Batches: a tenant's labels on sets of jobs (a dataset build), listed with their sizes, and the
//! inputs of a batch's statistics (its jobs by state and one stage's summaries).

use std::collections::BTreeMap;

use serde_json::Value;

use super::QueueStore;
use super::work::job_state_counts;
use crate::db::{Session, Sql, args};
use crate::{JobId, JobState, QueueError, QueueResult, TenantId};

/// Longest batch label.
pub const MAX_BATCH_LABEL_CHARS: usize = 64;

/// One batch of a tenant.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BatchSummary {
    /// Its label.
    pub label: String,
    /// Jobs in it.
    pub jobs: u64,
    /// When its first job joined, Unix milliseconds.
    pub created_at_ms: i64,
}

/// Checks a batch label: 1 to 64 ASCII letters, digits, `.`, `_` or `-`.
pub fn validate_batch_label(label: &str) -> QueueResult<()> {
    let ok = !label.is_empty()
        && label.len() <= MAX_BATCH_LABEL_CHARS
        && label
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'.' | b'_' | b'-'));
    if ok {
        Ok(())
    } else {
        Err(QueueError::Invalid(format!(
            "batch label {label:?} must be 1 to {MAX_BATCH_LABEL_CHARS} ASCII letters, digits, '.', '_' or '-'"
        )))
    }
}

static ADD: Sql = Sql::new(
    "INSERT INTO batch_items (tenant_id, batch, job_id, added_at_ms) VALUES ($1, $2, $3, {now})
     ON CONFLICT (tenant_id, batch, job_id) DO NOTHING",
);

static LIST: Sql = Sql::new(
    "SELECT batch, CAST(count(*) AS BIGINT) AS jobs, min(added_at_ms) AS created_at_ms
     FROM batch_items
     WHERE tenant_id = $1 AND ($2 IS NULL OR batch < $2)
     GROUP BY batch
     ORDER BY batch DESC
     LIMIT $3",
);

static JOB_STATES: Sql = Sql::new(
    "SELECT j.state, CAST(count(*) AS BIGINT) AS n
     FROM batch_items b JOIN jobs j ON j.id = b.job_id
     WHERE b.tenant_id = $1 AND b.batch = $2
     GROUP BY j.state",
);

static SUMMARIES: Sql = Sql::per_dialect(
    "SELECT r.output_manifest -> 'summary' AS summary
     FROM batch_items b JOIN stage_runs r ON r.job_id = b.job_id
     WHERE b.tenant_id = $1 AND b.batch = $2 AND r.stage_name = $3 AND r.state = 'succeeded'",
    "SELECT json_extract(r.output_manifest, '$.summary') AS summary
     FROM batch_items b JOIN stage_runs r ON r.job_id = b.job_id
     WHERE b.tenant_id = $1 AND b.batch = $2 AND r.stage_name = $3 AND r.state = 'succeeded'",
);

/// Largest page of [`QueueStore::list_batches`].
const MAX_PAGE: u32 = 1000;

/// Adds `job` to the tenant's batch `label` (no-op when already in it).
pub(crate) async fn add_to_batch(
    tx: &mut Session,
    tenant: TenantId,
    label: &str,
    job: JobId,
) -> QueueResult<()> {
    tx.execute(&ADD, args![tenant.0, label, job.0]).await?;
    Ok(())
}

impl QueueStore {
    /// The tenant's batches, by label descending, after `before` (the last label of the previous
    /// page), at most `limit` (capped at 1000).
    pub async fn list_batches(
        &self,
        tenant: TenantId,
        before: Option<&str>,
        limit: u32,
    ) -> QueueResult<Vec<BatchSummary>> {
        let mut session = self.db.read().await?;
        let rows = session
            .fetch_all(
                &LIST,
                args![
                    tenant.0,
                    before.map(str::to_owned),
                    i64::from(limit.clamp(1, MAX_PAGE))
                ],
            )
            .await?;
        rows.iter()
            .map(|row| {
                Ok(BatchSummary {
                    label: row.text("batch")?,
                    jobs: row.u64("jobs")?,
                    created_at_ms: row.i64("created_at_ms")?,
                })
            })
            .collect()
    }

    /// How many jobs of the tenant's batch `label` are in each state (empty: no such batch).
    pub async fn batch_job_states(
        &self,
        tenant: TenantId,
        label: &str,
    ) -> QueueResult<BTreeMap<JobState, u64>> {
        let mut session = self.db.read().await?;
        job_state_counts(
            &session
                .fetch_all(&JOB_STATES, args![tenant.0, label])
                .await?,
        )
    }

    /// The output-manifest summaries of `stage`'s succeeded runs over the jobs of the tenant's
    /// batch `label` (only the summaries: the manifests' artifact lists stay in the database).
    pub async fn batch_stage_summaries(
        &self,
        tenant: TenantId,
        label: &str,
        stage: &str,
    ) -> QueueResult<Vec<Value>> {
        let mut session = self.db.read().await?;
        let rows = session
            .fetch_all(&SUMMARIES, args![tenant.0, label, stage])
            .await?;
        let mut summaries = Vec::with_capacity(rows.len());
        for row in &rows {
            // Postgres reads a JSON null where SQLite reads SQL NULL: neither is a summary.
            if let Some(summary) = row.opt_json::<Value>("summary")?.filter(Value::is_object) {
                summaries.push(summary);
            }
        }
        Ok(summaries)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_labels_are_short_plain_ascii() {
        for good in ["seed", "uniphys-40k.part_3", &"a".repeat(64)] {
            assert!(validate_batch_label(good).is_ok(), "{good}");
        }
        for bad in ["", "two words", "ünï", "a/b", &"a".repeat(65)] {
            assert!(validate_batch_label(bad).is_err(), "{bad:?}");
        }
    }
}
