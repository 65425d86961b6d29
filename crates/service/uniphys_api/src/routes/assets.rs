//! `GET /v1/assets` (list with filters and keyset pages) and `GET /v1/assets/{asset_id}`.

use axum::Json;
use axum::extract::State;
use serde::{Deserialize, Serialize};
use uniphys_queue::{AssetId, JobDetail, JobFilter, JobState, TenantId};
use utoipa::{IntoParams, ToSchema};

use super::batches::batch_label;
use crate::ApiState;
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{ApiPath, ApiQuery, Tenant};
use crate::ids;
use crate::page::{next_cursor, page_limit};
use crate::state::Shared;
use crate::views::{AssetView, JobView};

/// Largest page of `GET /v1/assets`.
const MAX_PAGE: u32 = 1000;
/// Page size when `limit` is not given.
const DEFAULT_PAGE: u32 = 100;

/// Filters and page of a listing.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub(crate) struct ListParams {
    /// Only jobs in this state: `running`, `succeeded`, `dead` or `cancelled`.
    state: Option<String>,
    /// Only jobs of this asset (`asset_<n>` or `<n>`).
    asset: Option<String>,
    /// Only jobs in this batch (see `GET /v1/batches`).
    batch: Option<String>,
    /// Only jobs older than this one (`job_<n>`): the `next` of the previous page.
    before: Option<String>,
    /// Page size, 1 to 1000 (default 100).
    limit: Option<u32>,
}

/// One job of a listing, newest first.
#[derive(Debug, Serialize, ToSchema)]
pub struct JobListItem {
    /// `asset_<n>`.
    pub asset_id: String,
    /// `job_<n>`.
    pub job_id: String,
    /// The submitted file's name.
    pub file_name: String,
    /// `running`, `succeeded`, `dead` or `cancelled`.
    pub state: String,
    /// Higher runs first.
    pub priority: i32,
    /// Created, Unix milliseconds.
    pub created_at_ms: i64,
    /// Finished, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
}

/// A page of jobs.
#[derive(Debug, Serialize, ToSchema)]
pub struct AssetList {
    /// Newest first.
    pub items: Vec<JobListItem>,
    /// Pass as `before` for the next page; absent on the last page.
    pub next: Option<String>,
}

/// An asset with its latest job and each stage.
#[derive(Debug, Serialize, ToSchema)]
pub struct AssetDetail {
    /// The asset.
    pub asset: AssetView,
    /// Its latest job (absent only if retention removed it).
    pub job: Option<JobView>,
}

/// List the tenant's assets' jobs, newest first.
#[utoipa::path(
    get,
    path = "/v1/assets",
    tag = "assets",
    params(ListParams),
    responses(
        (status = 200, description = "A page of jobs", body = AssetList),
        (status = 400, description = "Unknown parameter, bad state, id or limit", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn list(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiQuery(params): ApiQuery<ListParams>,
) -> ApiResult<Json<AssetList>> {
    let limit = page_limit(params.limit, DEFAULT_PAGE, MAX_PAGE)?;
    if let Some(batch) = &params.batch {
        batch_label(batch)?;
    }
    let filter = JobFilter {
        state: params.state.as_deref().map(job_state).transpose()?,
        asset: params
            .asset
            .as_deref()
            .map(|a| ids::asset_id("asset", a))
            .transpose()?,
        before: params
            .before
            .as_deref()
            .map(|b| ids::job_id("before", b))
            .transpose()?,
        batch: params.batch.clone(),
        limit,
    };
    let jobs = state.store.list_jobs(tenant, &filter).await?;
    let ids: Vec<_> = jobs.iter().map(|j| j.id).collect();
    let next = next_cursor(&ids, limit);
    let items = jobs
        .iter()
        .map(|j| JobListItem {
            asset_id: j.asset_id.to_string(),
            job_id: j.id.to_string(),
            file_name: crate::views::file_name(&j.source_uri).to_owned(),
            state: j.state.to_string(),
            priority: j.priority,
            created_at_ms: j.created_at_ms,
            finished_at_ms: j.finished_at_ms,
        })
        .collect();
    Ok(Json(AssetList { items, next }))
}

fn job_state(raw: &str) -> ApiResult<JobState> {
    JobState::parse(raw).map_err(|_| {
        ApiError::bad_request(
            "invalid_query",
            format!("state must be one of running, succeeded, dead, cancelled; got {raw:?}"),
        )
    })
}

/// An asset, its latest job and each stage: state, attempts, errors, timings, cost, progress.
#[utoipa::path(
    get,
    path = "/v1/assets/{asset_id}",
    tag = "assets",
    params(("asset_id" = String, Path, description = "`asset_<n>` or `<n>`")),
    responses(
        (status = 200, description = "The asset", body = AssetDetail),
        (status = 400, description = "Invalid asset id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such asset for this tenant", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn get(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(raw): ApiPath<String>,
) -> ApiResult<Json<AssetDetail>> {
    let asset_id = ids::asset_id("asset_id", &raw)?;
    let asset = state.store.get_asset(tenant, asset_id).await?;
    let job = match latest_job(&state, tenant, asset_id).await? {
        Some(job) => {
            let progress = state.hooks.progress(job.id).await;
            Some(JobView::new(&job, &progress))
        }
        None => None,
    };
    Ok(Json(AssetDetail {
        asset: AssetView::from(&asset),
        job,
    }))
}

/// The newest job of `asset` (which the caller has checked belongs to `tenant`).
pub(crate) async fn latest_job(
    state: &ApiState,
    tenant: TenantId,
    asset: AssetId,
) -> ApiResult<Option<JobDetail>> {
    let filter = JobFilter {
        asset: Some(asset),
        limit: 1,
        ..JobFilter::default()
    };
    let Some(summary) = state
        .store
        .list_jobs(tenant, &filter)
        .await?
        .into_iter()
        .next()
    else {
        return Ok(None);
    };
    Ok(Some(state.store.get_job(tenant, summary.id).await?))
}
