//! Retention: finished jobs (with their runs, edges and events) are deleted after a while, so the
//! hot tables stay small. Assets stay: a later re-submit still de-duplicates against them.

use std::time::Duration;

use super::QueueStore;
use super::claim::millis;
use crate::QueueResult;
use crate::db::{Sql, args};

/// How long finished jobs are kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RetentionPolicy {
    /// Succeeded and cancelled jobs.
    pub finished: Duration,
    /// Dead jobs (kept longer: someone should look at them).
    pub dead: Duration,
    /// Jobs deleted per statement, to keep transactions and locks short.
    pub batch_size: u32,
}

impl Default for RetentionPolicy {
    /// Finished jobs 24 h, dead jobs 7 days (River's defaults), in batches of 1000.
    fn default() -> Self {
        Self {
            finished: Duration::from_secs(24 * 3600),
            dead: Duration::from_secs(7 * 24 * 3600),
            batch_size: 1000,
        }
    }
}

/// What a purge removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PurgeReport {
    /// Jobs deleted, with their stage runs and events.
    pub jobs: u64,
}

static PURGE: Sql = Sql::new(
    "WITH doomed AS MATERIALIZED (
         SELECT id FROM jobs
         WHERE (state IN ('succeeded', 'cancelled') AND finished_at_ms < {now} - $1)
            OR (state = 'dead' AND finished_at_ms < {now} - $2)
         LIMIT $3)
     DELETE FROM jobs WHERE id IN (SELECT id FROM doomed)",
);

impl QueueStore {
    /// Deletes jobs that finished longer ago than the policy allows, in batches, until none is
    /// left; running jobs are never touched.
    pub async fn purge_finished(&self, policy: &RetentionPolicy) -> QueueResult<PurgeReport> {
        let mut report = PurgeReport::default();
        loop {
            let mut tx = self.db.write_tx().await?;
            let deleted = tx
                .execute(
                    &PURGE,
                    args![
                        millis(policy.finished),
                        millis(policy.dead),
                        i64::from(policy.batch_size.max(1))
                    ],
                )
                .await?;
            tx.commit().await?;
            report.jobs += deleted;
            if deleted < u64::from(policy.batch_size.max(1)) {
                return Ok(report);
            }
        }
    }
}
