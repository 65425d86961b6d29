//! Fencing: every transition on a running stage run names the (run, attempt) it holds, and a
//! transition that matches nothing is explained here instead of silently succeeding.

use crate::db::{Session, Sql, args};
use crate::{JobId, JobState, Lease, QueueError, QueueResult, StageRunId, StageState, TenantId};

static RUN_STATE: Sql = Sql::new("SELECT state, attempt FROM stage_runs WHERE id = $1");
static LOCK_JOB_OF_RUN: Sql = Sql::new(
    "SELECT id, state FROM jobs WHERE id = (SELECT job_id FROM stage_runs WHERE id = $1) {for_update}",
);
static LOCK_TENANT_JOB: Sql =
    Sql::new("SELECT state FROM jobs WHERE id = $1 AND tenant_id = $2 {for_update}");

/// Explains why a fenced statement on `lease` matched no row.
pub(super) async fn lease_error(session: &mut Session, lease: &Lease) -> QueueError {
    let row = match session
        .fetch_optional(&RUN_STATE, args![lease.run_id.0])
        .await
    {
        Ok(row) => row,
        Err(e) => return e,
    };
    let Some(row) = row else {
        return QueueError::not_found("stage run", lease.run_id);
    };
    let (state, attempt) = match (row.text("state"), row.u32("attempt")) {
        (Ok(s), Ok(a)) => (s, a),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    if attempt == lease.attempt && state == StageState::Cancelled.as_str() {
        QueueError::Cancelled {
            run_id: lease.run_id,
        }
    } else {
        QueueError::LeaseLost {
            run_id: lease.run_id,
            attempt: lease.attempt,
            current_attempt: attempt,
            current_state: state,
        }
    }
}

/// Locks the job of `run` (Postgres `FOR UPDATE`) and returns its id and state.
pub(super) async fn lock_job_of_run(
    session: &mut Session,
    run: StageRunId,
) -> QueueResult<(JobId, JobState)> {
    let row = session
        .fetch_optional(&LOCK_JOB_OF_RUN, args![run.0])
        .await?
        .ok_or_else(|| QueueError::not_found("stage run", run))?;
    Ok((JobId(row.i64("id")?), JobState::parse(&row.text("state")?)?))
}

/// Locks `job` if it belongs to `tenant` and returns its state.
pub(super) async fn lock_tenant_job(
    session: &mut Session,
    tenant: TenantId,
    job: JobId,
) -> QueueResult<JobState> {
    let row = session
        .fetch_optional(&LOCK_TENANT_JOB, args![job.0, tenant.0])
        .await?
        .ok_or_else(|| QueueError::not_found("job", job))?;
    JobState::parse(&row.text("state")?)
}
