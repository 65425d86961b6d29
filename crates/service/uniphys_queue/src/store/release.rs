//! Releasing a held run without failing it: what a worker does on graceful shutdown, so its
//! runs are claimable at once instead of after their lease expires.

use super::QueueStore;
use super::events::{self, EventSubject};
use super::fencing;
use crate::db::{Sql, args};
use crate::{Lease, QueueResult};

// The attempt stays (it is the fencing token and must never go back); the budget grows by one
// so a release does not use up an attempt.
static RELEASE: Sql = Sql::new(
    "UPDATE stage_runs
     SET state = 'ready', run_after_ms = {now}, lease_expires_at_ms = NULL,
         max_attempts = max_attempts + 1
     WHERE id = $1 AND attempt = $2 AND state = 'running'
     RETURNING stage_name",
);

impl QueueStore {
    /// Puts the held run back to ready, claimable at once, without counting the attempt against
    /// its budget. Fails with `LeaseLost` or `Cancelled` (changing nothing) if the lease is no
    /// longer current.
    pub async fn release(&self, lease: &Lease) -> QueueResult<()> {
        let mut tx = self.db.write_tx().await?;
        let (job, _) = fencing::lock_job_of_run(&mut tx, lease.run_id).await?;
        let Some(row) = tx
            .fetch_optional(&RELEASE, args![lease.run_id.0, i64::from(lease.attempt)])
            .await?
        else {
            return Err(fencing::lease_error(&mut tx, lease).await);
        };
        let stage = row.text("stage_name")?;
        let subject = EventSubject {
            job,
            run: Some((lease.run_id, &stage)),
            attempt: Some(lease.attempt),
        };
        events::record(&mut tx, &subject, "stage_released", None).await?;
        tx.commit().await?;
        Ok(())
    }
}
