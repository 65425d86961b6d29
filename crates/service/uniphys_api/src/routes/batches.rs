//! `GET /v1/batches` (the tenant's batch labels) and `GET /v1/batches/{batch}/stats` (a batch's
//! dataset statistics). Submissions join a batch with `?batch=` on an upload or `"batch"` in a
//! manifest.

use axum::Json;
use axum::extract::State;
use serde::{Deserialize, Serialize};
use uniphys_queue::TenantId;
use uniphys_types::ServiceStage;
use utoipa::{IntoParams, ToSchema};

use crate::ApiState;
use crate::dataset_stats::{DatasetStats, dataset_stats};
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{ApiPath, ApiQuery, Tenant};
use crate::page::{next_cursor, page_limit};
use crate::routes::overview::JobCounts;
use crate::state::Shared;

/// The stage whose summaries hold each asset's dataset facts.
const CONVERT_STAGE: &str = ServiceStage::Convert.name();

/// A page of batches.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub(crate) struct BatchListParams {
    /// Only labels sorting before this one: the `next` of the previous page.
    before: Option<String>,
    /// Page size, 1 to 1000 (default 100).
    limit: Option<u32>,
}

/// One batch.
#[derive(Debug, Serialize, ToSchema)]
pub struct BatchView {
    /// Its label.
    pub batch: String,
    /// Jobs in it.
    pub jobs: u64,
    /// When its first job joined, Unix milliseconds.
    pub created_at_ms: i64,
}

/// A page of batches, labels descending.
#[derive(Debug, Serialize, ToSchema)]
pub struct BatchList {
    /// The batches.
    pub items: Vec<BatchView>,
    /// `before` for the next page; absent on the last.
    pub next: Option<String>,
}

/// A batch's statistics.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct BatchStatsResponse {
    /// Its label.
    pub batch: String,
    /// Its jobs by state.
    pub jobs: BatchJobs,
    /// Counts and distributions over its converted assets.
    #[serde(flatten)]
    pub dataset: DatasetStats,
}

/// A batch's jobs by state.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct BatchJobs {
    /// All of them.
    pub total: u64,
    /// By state.
    #[serde(flatten)]
    pub by_state: JobCounts,
}

/// The tenant's batches.
#[utoipa::path(
    get,
    path = "/v1/batches",
    tag = "assets",
    params(BatchListParams),
    responses(
        (status = 200, description = "A page of batches", body = BatchList),
        (status = 400, description = "Unknown parameter or bad limit", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn list(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiQuery(params): ApiQuery<BatchListParams>,
) -> ApiResult<Json<BatchList>> {
    let limit = page_limit(params.limit, 100, 1000)?;
    let batches = state
        .store
        .list_batches(tenant, params.before.as_deref(), limit)
        .await?;
    let labels: Vec<&str> = batches.iter().map(|b| b.label.as_str()).collect();
    let next = next_cursor(&labels, limit);
    let items = batches
        .into_iter()
        .map(|b| BatchView {
            batch: b.label,
            jobs: b.jobs,
            created_at_ms: b.created_at_ms,
        })
        .collect();
    Ok(Json(BatchList { items, next }))
}

/// A batch's dataset statistics: jobs by state; counts by category, material and joint type;
/// mass, size and part-count distributions over its converted assets.
#[utoipa::path(
    get,
    path = "/v1/batches/{batch}/stats",
    tag = "assets",
    params(("batch" = String, Path, description = "The batch label")),
    responses(
        (status = 200, description = "The statistics", body = BatchStatsResponse),
        (status = 400, description = "Malformed label", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such batch for this tenant", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn stats(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(batch): ApiPath<String>,
) -> ApiResult<Json<BatchStatsResponse>> {
    batch_label(&batch)?;
    let refresh = state.config.batch_stats_refresh;
    let key = (tenant, batch.clone());
    let stats = state
        .board
        .batches
        .get_or_compute(key, refresh, compute_stats(&state, tenant, batch))
        .await?;
    Ok(Json(BatchStatsResponse::clone(&stats)))
}

/// A batch's statistics computed now (404 for a batch with no jobs).
pub(crate) async fn compute_stats(
    state: &ApiState,
    tenant: TenantId,
    batch: String,
) -> ApiResult<BatchStatsResponse> {
    let states = state.store.batch_job_states(tenant, &batch).await?;
    if states.is_empty() {
        return Err(ApiError::NotFound(format!("no batch {batch:?}")));
    }
    let by_state = JobCounts::from_states(states);
    let summaries = state
        .store
        .batch_stage_summaries(tenant, &batch, CONVERT_STAGE)
        .await?;
    Ok(BatchStatsResponse {
        batch,
        jobs: BatchJobs {
            total: by_state.total(),
            by_state,
        },
        dataset: dataset_stats(&summaries),
    })
}

/// Checks a batch label, answering 400 with the rule.
pub(crate) fn batch_label(label: &str) -> ApiResult<()> {
    uniphys_queue::validate_batch_label(label)
        .map_err(|e| ApiError::bad_request("invalid_batch", e.to_string()))
}
