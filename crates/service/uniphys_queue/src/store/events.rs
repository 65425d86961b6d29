//! The append-only event history of a job.

use serde_json::Value;

use super::QueueStore;
use crate::db::{Session, Sql, args};
use crate::{JobId, QueueError, QueueResult, StageRunId, TenantId};

/// One recorded transition.
#[derive(Clone, Debug, PartialEq)]
pub struct JobEvent {
    /// Increases with time.
    pub id: i64,
    /// The stage run it concerns, if any.
    pub stage_run_id: Option<StageRunId>,
    /// Its stage name, if any.
    pub stage_name: Option<String>,
    /// `job_created`, `stage_succeeded`, `stage_failed`, `stage_dead`, `job_succeeded`,
    /// `job_dead`, `job_cancelled`, `job_retried`.
    pub kind: String,
    /// The attempt it concerns, if any.
    pub attempt: Option<u32>,
    /// Kind-specific details (error message, backoff, counts).
    pub detail: Option<Value>,
    /// When, in Unix milliseconds (database clock).
    pub at_ms: i64,
}

static INSERT: Sql = Sql::new(
    "INSERT INTO events (job_id, stage_run_id, stage_name, kind, attempt, detail, at_ms)
     VALUES ($1, $2, $3, $4, $5, $6, {now})",
);

static LIST: Sql = Sql::new(
    "SELECT e.id, e.stage_run_id, e.stage_name, e.kind, e.attempt, e.detail, e.at_ms
     FROM events e JOIN jobs j ON j.id = e.job_id
     WHERE e.job_id = $1 AND j.tenant_id = $2
     ORDER BY e.id",
);

/// What an event is about.
pub(super) struct EventSubject<'a> {
    pub job: JobId,
    pub run: Option<(StageRunId, &'a str)>,
    pub attempt: Option<u32>,
}

impl EventSubject<'_> {
    pub(super) fn job(job: JobId) -> Self {
        Self {
            job,
            run: None,
            attempt: None,
        }
    }
}

pub(super) async fn record(
    session: &mut Session,
    subject: &EventSubject<'_>,
    kind: &str,
    detail: Option<Value>,
) -> QueueResult<()> {
    let (run_id, stage) = match subject.run {
        Some((id, stage)) => (Some(id.0), Some(stage.to_owned())),
        None => (None, None),
    };
    session
        .execute(
            &INSERT,
            args![
                subject.job.0,
                run_id,
                stage,
                kind,
                subject.attempt.map(i64::from),
                detail
            ],
        )
        .await?;
    Ok(())
}

impl QueueStore {
    /// Returns the events of `job`, oldest first.
    pub async fn job_events(&self, tenant: TenantId, job: JobId) -> QueueResult<Vec<JobEvent>> {
        let mut session = self.db.read().await?;
        let rows = session.fetch_all(&LIST, args![job.0, tenant.0]).await?;
        rows.iter()
            .map(|row| {
                Ok(JobEvent {
                    id: row.i64("id")?,
                    stage_run_id: row.opt_i64("stage_run_id")?.map(StageRunId),
                    stage_name: row.opt_text("stage_name")?,
                    kind: row.text("kind")?,
                    attempt: row
                        .opt_i64("attempt")?
                        .map(|a| {
                            u32::try_from(a)
                                .map_err(|_| QueueError::CorruptRow(format!("event attempt {a}")))
                        })
                        .transpose()?,
                    detail: row.opt_json("detail")?,
                    at_ms: row.i64("at_ms")?,
                })
            })
            .collect()
    }
}
