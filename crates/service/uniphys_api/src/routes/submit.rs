//! `POST /v1/assets`: submit an asset by upload; and the submission steps every way of
//! submitting shares (backlog check, storing the source, creating the job).

use std::collections::BTreeSet;

use axum::Json;
use axum::body::Body;
use axum::extract::State;
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use uniphys_queue::{JobState, NewAsset, QueueError, TenantId};
use utoipa::{IntoParams, ToSchema};

use crate::ApiState;
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{ApiQuery, Tenant};
use crate::routes::batches::batch_label;
use crate::state::Shared;
use crate::upload::{Spooled, check_archive, empty_source, source_filename, spool_body, too_large};

/// Query of an upload.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub(crate) struct UploadParams {
    /// Name of the file, with its extension (`cabinet.glb`); stages choose their reader by it.
    filename: String,
    /// Higher runs first (default 0).
    priority: Option<i32>,
    /// Adds the job to this batch of the tenant (1 to 64 ASCII letters, digits, `.`, `_`, `-`).
    batch: Option<String>,
}

/// Where a submission goes in the queue.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Placement<'a> {
    /// Higher runs first; `None`: the job spec's.
    pub priority: Option<i32>,
    /// The batch the job joins.
    pub batch: Option<&'a str>,
}

/// The answer to a submission.
#[derive(Debug, Serialize, ToSchema)]
pub struct SubmitResponse {
    /// `asset_<n>`.
    pub asset_id: String,
    /// `job_<n>`: the job created for it, or its latest job on a re-submit.
    pub job_id: String,
    /// Whether the asset is new (201); `false` for a re-submit of the same content (200).
    pub created: bool,
    /// `sha256:<hex>` of the content.
    pub content_digest: String,
    /// Object-store key of the stored content.
    pub source_key: String,
    /// Size of the content.
    pub size_bytes: u64,
    /// The job's state: `running` for a new job; on a re-submit, that of the existing job
    /// (`running`, `succeeded`, `dead` or `cancelled`).
    pub job_state: String,
    /// On a re-submit whose job is dead or cancelled: the path that runs it again (`POST`, see
    /// `/v1/jobs/{job_id}/retry`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub retry: Option<String>,
}

/// Submit an asset by uploading its file.
///
/// The body is the file's bytes, streamed to disk while hashed. An asset of several files (a
/// URDF folder with its meshes, an OBJ with its MTL and textures, a glTF with external buffers)
/// is sent as one archive (`.zip`, `.tar`, `.tar.gz`, `.tgz`); it is read whole and checked
/// before it is stored, and its main file is found in it. Submitting the same content again
/// answers 200 with the same ids and the job's state; a dead or cancelled job is not run again
/// by a re-submit, the answer names its retry path instead.
#[utoipa::path(
    post,
    path = "/v1/assets",
    tag = "assets",
    params(UploadParams),
    request_body(content = Vec<u8>, content_type = "application/octet-stream", description = "The file's bytes."),
    responses(
        (status = 201, description = "Asset and job created", body = SubmitResponse),
        (status = 200, description = "Same content submitted before: the existing ids", body = SubmitResponse),
        (status = 400, description = "Malformed query", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 413, description = "Upload over the size limit; nothing stored", body = ErrorBody),
        (status = 415, description = "A file type the pipeline does not read (by its extension), nor an archive", body = ErrorBody),
        (status = 422, description = "Filename without an extension, an empty body, or an archive refused (a path out of its folder, a link, too many entries or bytes, no single asset in it)", body = ErrorBody),
        (status = 429, description = "Tenant backlog full; see Retry-After", body = ErrorBody),
        (status = 503, description = "Database or object store unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn upload(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiQuery(params): ApiQuery<UploadParams>,
    headers: HeaderMap,
    body: Body,
) -> ApiResult<Response> {
    let filename = source_filename(&params.filename)?;
    if let Some(batch) = &params.batch {
        batch_label(batch)?;
    }
    let max = state.config.max_upload_bytes;
    let declared = headers
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.parse::<u64>().ok());
    if declared.is_some_and(|n| n > max) {
        return Err(too_large(max));
    }
    if declared == Some(0) {
        return Err(empty_source("the upload"));
    }
    check_backlog(&state, tenant, 1).await?;
    let spooled = spool_body(
        body,
        state.config.upload_tmp_dir.clone(),
        max,
        state.config.body_read_timeout,
    )
    .await?;
    if spooled.size_bytes == 0 {
        return Err(empty_source("the upload"));
    }
    let placement = Placement {
        priority: params.priority,
        batch: params.batch.as_deref(),
    };
    let (created, answer) = store_and_submit(&state, tenant, spooled, &filename, placement).await?;
    Ok(submitted(created, answer))
}

/// Refuses with 429 when `jobs` more jobs would take the tenant's unfinished stage runs over its cap.
pub(crate) async fn check_backlog(state: &ApiState, tenant: TenantId, jobs: u64) -> ApiResult<()> {
    let cap = state.config.max_backlog_per_tenant;
    let adding = jobs.saturating_mul(state.config.job_spec.stages.len() as u64);
    let mut backlog = state.backlog.backlog(state, tenant).await?;
    if backlog.saturating_add(adding) > cap {
        // The estimate may count runs that have finished since: count again before refusing.
        backlog = state.backlog.recount(state, tenant).await?;
    }
    if backlog.saturating_add(adding) > cap {
        return Err(ApiError::Backpressure {
            message: format!(
                "backlog full: the tenant has {backlog} unfinished stage runs and this request adds {adding} (cap {cap}); retry later"
            ),
            retry_after_secs: state.config.backlog_retry_after_secs,
        });
    }
    Ok(())
}

/// Stores a spooled source under `sources/t{tenant}/{sha256}/{filename}` and submits it;
/// returns whether the asset is new, and the answer.
pub(crate) async fn store_and_submit(
    state: &ApiState,
    tenant: TenantId,
    spooled: Spooled,
    filename: &str,
    placement: Placement<'_>,
) -> ApiResult<(bool, SubmitResponse)> {
    check_archive(&spooled.path, filename, state.config.archive_limits).await?;
    let key = format!("sources/t{}/{}/{filename}", tenant.0, spooled.sha256_hex);
    state.artifacts.put_file(&key, &spooled.path).await?;
    drop(spooled.path);
    let mut spec = state.config.job_spec.clone();
    if let Some(priority) = placement.priority {
        spec.priority = priority;
    }
    spec.trace_parent = state.hooks.current_traceparent();
    let asset = NewAsset {
        content_digest: format!("sha256:{}", spooled.sha256_hex),
        source_uri: key,
        size_bytes: spooled.size_bytes,
    };
    // Far from the cap the estimate lets the submission through; near it the submission's
    // transaction counts exactly, so concurrent requests cannot take the tenant over together.
    let cap = state.config.max_backlog_per_tenant;
    let adding = spec.stages.len() as u64;
    let admission = state.backlog.admit(state, tenant, adding, cap).await?;
    let submitted = state
        .store
        .submit_capped(tenant, &asset, &spec, placement.batch, admission.exact_cap)
        .await;
    drop(admission);
    let submission = match submitted {
        Ok(submission) => submission,
        Err(QueueError::BacklogFull { backlog, .. }) => {
            // Refused content is new (known content makes no job): its copy goes too.
            if let Err(delete) = state.artifacts.delete(&asset.source_uri).await {
                tracing::warn!(key = %asset.source_uri, error = %delete, "a refused upload's copy was not removed");
            }
            return Err(ApiError::Backpressure {
                message: format!(
                    "backlog full: the tenant has {backlog} unfinished stage runs and this upload adds {adding} (cap {cap}, counting the submissions under way); retry later"
                ),
                retry_after_secs: state.config.backlog_retry_after_secs,
            });
        }
        Err(e) => return Err(e.into()),
    };
    if submission.job_created {
        let roots: BTreeSet<String> = spec
            .stages
            .iter()
            .filter(|s| s.depends_on.is_empty())
            .map(|s| s.name.clone())
            .collect();
        let roots: Vec<String> = roots.into_iter().collect();
        state.hooks.on_stages_ready(&roots).await;
    }
    tracing::info!(
        asset_id = %submission.asset_id,
        job_id = %submission.job_id,
        created = submission.asset_created,
        "asset submitted"
    );
    let mut source_key = asset.source_uri;
    if !submission.asset_created {
        // Known content keeps the object it was first stored as; the same bytes under another
        // name are not kept a second time.
        let known = state
            .store
            .get_asset(tenant, submission.asset_id)
            .await?
            .source_uri;
        if known != source_key {
            if let Err(e) = state.artifacts.delete(&source_key).await {
                tracing::warn!(key = %source_key, error = %e, "a duplicate upload's copy was not removed");
            }
            source_key = known;
        }
    }
    let job_state = if submission.job_created {
        JobState::Running
    } else {
        state.store.get_job(tenant, submission.job_id).await?.state
    };
    let retry = matches!(job_state, JobState::Dead | JobState::Cancelled)
        .then(|| format!("/v1/jobs/{}/retry", submission.job_id));
    let answer = SubmitResponse {
        asset_id: submission.asset_id.to_string(),
        job_id: submission.job_id.to_string(),
        created: submission.asset_created,
        content_digest: asset.content_digest,
        source_key,
        size_bytes: asset.size_bytes,
        job_state: job_state.to_string(),
        retry,
    };
    Ok((submission.asset_created, answer))
}

/// 201 with `Location` for a new asset, 200 for a re-submit.
pub(crate) fn submitted(created: bool, answer: SubmitResponse) -> Response {
    let status = if created {
        StatusCode::CREATED
    } else {
        StatusCode::OK
    };
    let location = HeaderValue::from_str(&format!("/v1/assets/{}", answer.asset_id)).ok();
    let mut response = (status, Json(answer)).into_response();
    if let Some(location) = location {
        response.headers_mut().insert(header::LOCATION, location);
    }
    response
}
