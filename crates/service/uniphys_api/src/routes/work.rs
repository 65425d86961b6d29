//! `GET /v1/work`: the stage runs the tenant is waiting on (of its running jobs) or that were
//! dead-lettered (of its dead jobs), newest jobs first, with their last error and live progress.

use std::collections::BTreeMap;

use axum::Json;
use axum::extract::State;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use uniphys_queue::{JobId, JobState, StageState};
use utoipa::{IntoParams, ToSchema};

use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{ApiQuery, Tenant};
use crate::ids;
use crate::page::{next_cursor, page_limit};
use crate::state::Shared;
use crate::views::{ErrorView, file_name};

/// Largest page, in jobs.
const MAX_JOBS: u32 = 200;

/// Which work to list.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub(crate) struct WorkParams {
    /// `running` (waiting or running stages of running jobs) or `dead` (dead letters).
    state: String,
    /// Only jobs older than this one (`job_<n>`): the `next` of the previous page.
    before: Option<String>,
    /// Jobs per page, 1 to 200 (default 50).
    limit: Option<u32>,
}

/// One stage run of a listed job.
#[derive(Debug, Serialize, ToSchema)]
pub struct WorkItemView {
    /// `job_<n>`.
    pub job_id: String,
    /// `asset_<n>`.
    pub asset_id: String,
    /// The submitted file's name.
    pub file_name: String,
    /// `run_<n>`.
    pub run_id: String,
    /// Stage name.
    pub stage: String,
    /// `ready` (waiting for a worker or a retry backoff), `running`, `dead`, or `blocked` (a dead
    /// job's stage behind its dead one).
    pub state: String,
    /// Attempts so far.
    pub attempt: u32,
    /// Attempts allowed.
    pub max_attempts: u32,
    /// The worker of the current or last attempt.
    pub worker_id: Option<String>,
    /// Current attempt started, Unix milliseconds.
    pub started_at_ms: Option<i64>,
    /// Claimable from, Unix milliseconds.
    pub run_after_ms: i64,
    /// Failed attempts so far.
    pub errors: usize,
    /// The latest failed attempt.
    pub last_error: Option<ErrorView>,
    /// Live progress of a running stage, as its worker reports it.
    #[schema(value_type = Option<Object>)]
    pub progress: Option<Value>,
}

/// A page of work.
#[derive(Debug, Serialize, ToSchema)]
pub struct WorkList {
    /// Newest job first, then in stage order.
    pub items: Vec<WorkItemView>,
    /// `before` for the next page; absent on the last.
    pub next: Option<String>,
}

/// The tenant's open or dead-lettered stage runs, newest jobs first.
#[utoipa::path(
    get,
    path = "/v1/work",
    tag = "jobs",
    params(WorkParams),
    responses(
        (status = 200, description = "A page of stage runs", body = WorkList),
        (status = 400, description = "Unknown parameter, bad state, id or limit", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn list(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiQuery(params): ApiQuery<WorkParams>,
) -> ApiResult<Json<WorkList>> {
    let job_state = match params.state.as_str() {
        "running" => JobState::Running,
        "dead" => JobState::Dead,
        other => {
            return Err(ApiError::bad_request(
                "invalid_query",
                format!("state must be running or dead, got {other:?}"),
            ));
        }
    };
    let limit = page_limit(params.limit, 50, MAX_JOBS)?;
    let before = params
        .before
        .as_deref()
        .map(|b| ids::job_id("before", b))
        .transpose()?;
    let work = state
        .store
        .list_work(tenant, job_state, before, limit)
        .await?;
    let mut jobs: Vec<JobId> = work.iter().map(|w| w.job_id).collect();
    jobs.dedup();
    let next = next_cursor(&jobs, limit);
    let mut progress: BTreeMap<JobId, BTreeMap<String, Value>> = BTreeMap::new();
    for item in work.iter().filter(|w| w.state == StageState::Running) {
        if let std::collections::btree_map::Entry::Vacant(slot) = progress.entry(item.job_id) {
            slot.insert(state.hooks.progress(item.job_id).await);
        }
    }
    let items = work
        .iter()
        .map(|w| WorkItemView {
            job_id: w.job_id.to_string(),
            asset_id: w.asset_id.to_string(),
            file_name: file_name(&w.source_uri).to_owned(),
            run_id: w.run_id.to_string(),
            stage: w.stage_name.clone(),
            state: w.state.to_string(),
            attempt: w.attempt,
            max_attempts: w.max_attempts,
            worker_id: w.worker_id.as_ref().map(ToString::to_string),
            started_at_ms: w.started_at_ms,
            run_after_ms: w.run_after_ms,
            errors: w.errors.len(),
            last_error: w.errors.last().map(ErrorView::from),
            progress: progress
                .get(&w.job_id)
                .and_then(|p| p.get(&w.stage_name))
                .cloned(),
        })
        .collect();
    Ok(Json(WorkList { items, next }))
}
