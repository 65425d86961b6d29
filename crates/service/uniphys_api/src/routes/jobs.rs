//! `GET /v1/jobs/{job_id}`, its events, and `cancel` and `retry`.

use axum::Json;
use axum::extract::State;
use serde::Serialize;
use serde_json::Value;
use utoipa::ToSchema;

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{ApiPath, Tenant};
use crate::ids;
use crate::state::Shared;
use crate::views::JobView;

/// One event in a job's history.
#[derive(Debug, Serialize, ToSchema)]
pub struct EventView {
    /// Event number (increasing).
    pub id: i64,
    /// `run_<n>` of the stage run it concerns.
    pub run_id: Option<String>,
    /// The stage it concerns.
    pub stage: Option<String>,
    /// `job_created`, `stage_claimed`, `stage_failed`, `job_cancelled`, …
    pub kind: String,
    /// The attempt it concerns.
    pub attempt: Option<u32>,
    /// Kind-specific detail.
    #[schema(value_type = Option<Object>)]
    pub detail: Option<Value>,
    /// When, Unix milliseconds.
    pub at_ms: i64,
}

/// A job's events, oldest first.
#[derive(Debug, Serialize, ToSchema)]
pub struct EventList {
    /// Oldest first.
    pub items: Vec<EventView>,
}

/// What a cancel changed.
#[derive(Debug, Serialize, ToSchema)]
pub struct CancelResponse {
    /// `job_<n>`.
    pub job_id: String,
    /// Unfinished stage runs that were cancelled.
    pub runs_cancelled: u64,
}

/// What a retry requeued.
#[derive(Debug, Serialize, ToSchema)]
pub struct RetryResponse {
    /// `job_<n>`.
    pub job_id: String,
    /// Stages whose dead-lettered runs are claimable again (with a fresh attempt budget).
    pub requeued: Vec<String>,
}

/// A job and each of its stages.
#[utoipa::path(
    get,
    path = "/v1/jobs/{job_id}",
    tag = "jobs",
    params(("job_id" = String, Path, description = "`job_<n>` or `<n>`")),
    responses(
        (status = 200, description = "The job", body = JobView),
        (status = 400, description = "Invalid job id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such job for this tenant", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn get(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(raw): ApiPath<String>,
) -> ApiResult<Json<JobView>> {
    let job_id = ids::job_id("job_id", &raw)?;
    let job = state.store.get_job(tenant, job_id).await?;
    let progress = state.hooks.progress(job_id).await;
    Ok(Json(JobView::new(&job, &progress)))
}

/// A job's events: creation, claims, failures, completions, cancellation, retries.
#[utoipa::path(
    get,
    path = "/v1/jobs/{job_id}/events",
    tag = "jobs",
    params(("job_id" = String, Path, description = "`job_<n>` or `<n>`")),
    responses(
        (status = 200, description = "The events, oldest first", body = EventList),
        (status = 400, description = "Invalid job id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such job for this tenant", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn events(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(raw): ApiPath<String>,
) -> ApiResult<Json<EventList>> {
    let job_id = ids::job_id("job_id", &raw)?;
    // An empty list would not tell a foreign job from one without events: check ownership.
    state.store.get_job(tenant, job_id).await?;
    let events = state.store.job_events(tenant, job_id).await?;
    let items = events
        .into_iter()
        .map(|e| EventView {
            id: e.id,
            run_id: e.stage_run_id.map(|r| r.to_string()),
            stage: e.stage_name,
            kind: e.kind,
            attempt: e.attempt,
            detail: e.detail,
            at_ms: e.at_ms,
        })
        .collect();
    Ok(Json(EventList { items }))
}

/// Cancel a running or dead-lettered job; its unfinished stages are cancelled.
#[utoipa::path(
    post,
    path = "/v1/jobs/{job_id}/cancel",
    tag = "jobs",
    params(("job_id" = String, Path, description = "`job_<n>` or `<n>`")),
    responses(
        (status = 200, description = "Cancelled", body = CancelResponse),
        (status = 400, description = "Invalid job id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such job for this tenant", body = ErrorBody),
        (status = 409, description = "The job already finished (succeeded or cancelled)", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn cancel(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(raw): ApiPath<String>,
) -> ApiResult<Json<CancelResponse>> {
    let job_id = ids::job_id("job_id", &raw)?;
    let runs_cancelled = state.store.cancel_job(tenant, job_id).await?;
    tracing::info!(%job_id, runs_cancelled, "job cancelled");
    Ok(Json(CancelResponse {
        job_id: job_id.to_string(),
        runs_cancelled,
    }))
}

/// Retry a dead-lettered or cancelled job: its dead and cancelled stages become claimable again
/// with a fresh attempt budget (a stage still waiting on another waits again).
#[utoipa::path(
    post,
    path = "/v1/jobs/{job_id}/retry",
    tag = "jobs",
    params(("job_id" = String, Path, description = "`job_<n>` or `<n>`")),
    responses(
        (status = 200, description = "Requeued", body = RetryResponse),
        (status = 400, description = "Invalid job id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such job for this tenant", body = ErrorBody),
        (status = 409, description = "The job is running or succeeded", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn retry(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(raw): ApiPath<String>,
) -> ApiResult<Json<RetryResponse>> {
    let job_id = ids::job_id("job_id", &raw)?;
    let runs = state.store.retry_job(tenant, job_id).await?;
    let mut stages: Vec<String> = runs.into_iter().map(|r| r.stage_name).collect();
    stages.sort();
    stages.dedup();
    state.hooks.on_stages_ready(&stages).await;
    tracing::info!(%job_id, requeued = stages.len(), "job retried");
    Ok(Json(RetryResponse {
        job_id: job_id.to_string(),
        requeued: stages,
    }))
}
