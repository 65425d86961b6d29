//! `POST /v1/assets/by-url` and `POST /v1/batches`: submit assets already in the service's object
//! store. The object is copied (streamed, hashed) to the tenant's content-addressed source key, so
//! the recorded digest stays true even if the original is later overwritten. A key ending in `/`
//! names a folder of objects (a URDF with its meshes): they are packed, in key order, into one
//! tar with fixed times and owners, so the same objects make the same asset.

use axum::Json;
use axum::extract::State;
use axum::response::Response;
use futures::{StreamExt, TryStreamExt};
use serde::{Deserialize, Serialize};
use uniphys_archive::{ArchiveKind, DeterministicTar};
use uniphys_queue::TenantId;
use utoipa::ToSchema;

use super::batches::batch_label;
use super::submit::{Placement, SubmitResponse, check_backlog, store_and_submit, submitted};
use crate::ApiState;
use crate::error::{ApiError, ApiResult, ErrorBody, ErrorDetail};
use crate::extract::{ApiJson, Tenant};
use crate::state::Shared;
use crate::upload::{
    Spooled, digest_file, empty_source, source_filename, spool, spool_file, too_large,
};

/// Batch items submitted at the same time.
const BATCH_CONCURRENCY: usize = 8;

/// An asset to import from the service's object store.
#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ByUrlRequest {
    /// Object-store key, e.g. `incoming/t1/cabinet.glb` (under one of the tenant's prefixes), or
    /// a prefix ending in `/` whose objects are one asset's files (`incoming/t1/45213/`: a URDF
    /// folder, an OBJ with its MTL and textures).
    pub url: String,
    /// Name to store it under, with its extension; defaults to the key's last component (for a
    /// prefix, its last component with `.tar`).
    pub filename: Option<String>,
    /// Higher runs first (default 0).
    pub priority: Option<i32>,
    /// Adds the job to this batch of the tenant (`GET /v1/batches/{batch}/stats`); in a
    /// manifest, overrides the manifest's `batch`.
    pub batch: Option<String>,
}

/// A batch manifest.
#[derive(Debug, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct BatchRequest {
    /// The assets; all are validated before any is submitted.
    pub items: Vec<ByUrlRequest>,
    /// The batch every item joins (1 to 64 ASCII letters, digits, `.`, `_`, `-`); items without
    /// one of their own join none when absent.
    pub batch: Option<String>,
    /// `true` (the default): one invalid item refuses the whole manifest (422) and nothing is
    /// submitted. `false`: each invalid item gets its own error result and the valid ones are
    /// submitted (a large manifest sent in chunks, where one missing object must not hold back
    /// the rest).
    pub all_or_nothing: Option<bool>,
}

/// The result of one batch item.
#[derive(Debug, Serialize, ToSchema)]
pub struct BatchItemResult {
    /// Position in the manifest.
    pub index: usize,
    /// HTTP status this item would have answered alone (201, 200, or an error status).
    pub status: u16,
    /// The submission, when it succeeded.
    pub submission: Option<SubmitResponse>,
    /// The error, when it failed.
    pub error: Option<ErrorDetail>,
}

/// The answer to a batch.
#[derive(Debug, Serialize, ToSchema)]
pub struct BatchResponse {
    /// One result per item, in manifest order.
    pub items: Vec<BatchItemResult>,
}

/// A validated import: the key to read, the name to store it under.
struct Import {
    key: String,
    /// For a prefix: the keys under it (sorted), packed into one tar.
    folder: Option<Vec<String>>,
    filename: String,
    priority: Option<i32>,
    batch: Option<String>,
}

/// Submit an asset already in the service's object store.
///
/// `url` is one object's key, or a prefix ending in `/` whose objects are one asset's files
/// (packed into a tar in key order, so the same objects are the same asset). An archive object
/// is checked as an upload is.
#[utoipa::path(
    post,
    path = "/v1/assets/by-url",
    tag = "assets",
    request_body = ByUrlRequest,
    responses(
        (status = 201, description = "Asset and job created", body = SubmitResponse),
        (status = 200, description = "Same content submitted before: the existing ids", body = SubmitResponse),
        (status = 400, description = "Malformed JSON or unknown field", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 413, description = "Object over the size limit", body = ErrorBody),
        (status = 415, description = "A file type the pipeline does not read (by its extension), nor an archive", body = ErrorBody),
        (status = 422, description = "No such object, an empty one, a key outside the tenant's prefixes, a bad filename, or an archive refused (see POST /v1/assets)", body = ErrorBody),
        (status = 429, description = "Tenant backlog full; see Retry-After", body = ErrorBody),
        (status = 503, description = "Database or object store unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn by_url(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiJson(request): ApiJson<ByUrlRequest>,
) -> ApiResult<Response> {
    let import = validate(&state, tenant, &request, None).await?;
    check_backlog(&state, tenant, 1).await?;
    let (created, answer) = run_import(&state, tenant, import).await?;
    Ok(submitted(created, answer))
}

/// Submit many assets from a manifest.
///
/// Every item is validated first (all or nothing: one bad item answers 422 naming each bad item
/// and submits none; with `all_or_nothing: false` a bad item gets its own error result and the
/// others go on); then each is submitted and gets its own result. Re-submitting known content
/// answers 200 for it with the existing job, so a manifest sent again makes no new jobs.
#[utoipa::path(
    post,
    path = "/v1/batches",
    tag = "assets",
    request_body = BatchRequest,
    responses(
        (status = 200, description = "Per-item results", body = BatchResponse),
        (status = 400, description = "Malformed manifest or unknown field", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 413, description = "An object over the size limit", body = ErrorBody),
        (status = 422, description = "Empty or too long, or bad items (each named: a missing or empty object, a file type the pipeline does not read, ...)", body = ErrorBody),
        (status = 429, description = "Tenant backlog cannot take the batch; see Retry-After", body = ErrorBody),
        (status = 503, description = "Database or object store unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn batch(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiJson(request): ApiJson<BatchRequest>,
) -> ApiResult<Json<BatchResponse>> {
    let max = state.config.max_batch_items;
    if request.items.is_empty() {
        return Err(ApiError::Unprocessable("items must not be empty".into()));
    }
    if let Some(batch) = &request.batch {
        batch_label(batch)?;
    }
    if request.items.len() > max {
        return Err(ApiError::Unprocessable(format!(
            "a batch holds at most {max} items, got {}",
            request.items.len()
        )));
    }
    let checks: Vec<_> = request
        .items
        .iter()
        .map(|item| validate(&state, tenant, item, request.batch.as_deref()))
        .collect();
    let checks: Vec<ApiResult<Import>> = futures::stream::iter(checks)
        .buffered(BATCH_CONCURRENCY)
        .collect()
        .await;
    let mut imports = Vec::with_capacity(checks.len());
    let mut problems = Vec::new();
    let mut refused = Vec::new();
    for (index, check) in checks.into_iter().enumerate() {
        match check {
            Ok(import) => imports.push((index, import)),
            Err(e @ (ApiError::Unavailable(_) | ApiError::Internal(_))) => return Err(e),
            Err(e) => {
                problems.push(format!("items[{index}]: {e}"));
                refused.push(failed_item(index, &e));
            }
        }
    }
    let all_or_nothing = request.all_or_nothing.unwrap_or(true);
    if all_or_nothing && !problems.is_empty() {
        return Err(ApiError::Unprocessable(format!(
            "{} of {} items are invalid, nothing was submitted: {}",
            problems.len(),
            request.items.len(),
            problems.join("; ")
        )));
    }
    check_backlog(&state, tenant, imports.len() as u64).await?;
    let state = &state;
    let submissions: Vec<_> = imports
        .into_iter()
        .map(|(index, import)| async move {
            match run_import(state, tenant, import).await {
                Ok((created, answer)) => BatchItemResult {
                    index,
                    status: if created { 201 } else { 200 },
                    submission: Some(answer),
                    error: None,
                },
                Err(e) => {
                    if e.to_body().0.is_server_error() {
                        tracing::error!(index, error = %e, "batch item failed");
                    }
                    failed_item(index, &e)
                }
            }
        })
        .collect();
    let mut items: Vec<BatchItemResult> = futures::stream::iter(submissions)
        .buffered(BATCH_CONCURRENCY)
        .collect()
        .await;
    items.extend(refused);
    items.sort_by_key(|item| item.index);
    Ok(Json(BatchResponse { items }))
}

/// The result of item `index` that failed with `e`.
fn failed_item(index: usize, e: &ApiError) -> BatchItemResult {
    let (status, body) = e.to_body();
    BatchItemResult {
        index,
        status: status.as_u16(),
        submission: None,
        error: Some(body.error),
    }
}

/// Checks the key (form, tenant prefix, existence, size) and the filename.
async fn validate(
    state: &ApiState,
    tenant: TenantId,
    request: &ByUrlRequest,
    manifest_batch: Option<&str>,
) -> ApiResult<Import> {
    let is_prefix = request.url.ends_with('/');
    let key = object_key(state, tenant, request.url.trim_end_matches('/'))?;
    let batch = request.batch.as_deref().or(manifest_batch);
    if let Some(batch) = batch {
        batch_label(batch)?;
    }
    let last = key.rsplit('/').next().unwrap_or_default();
    let raw_name = match (&request.filename, is_prefix) {
        (Some(name), _) => name.clone(),
        (None, true) => format!("{last}.tar"),
        (None, false) => last.to_owned(),
    };
    let filename = source_filename(&raw_name)?;
    let folder = if is_prefix {
        if ArchiveKind::from_name(&filename) != Some(ArchiveKind::Tar) {
            return Err(ApiError::Unprocessable(format!(
                "a prefix's objects are packed into a tar: filename must end in .tar, got {raw_name:?}"
            )));
        }
        Some(folder_keys(state, &key).await?)
    } else {
        let Some(size_bytes) = state.artifacts.head(&key).await? else {
            return Err(ApiError::Unprocessable(format!("no object at {key}")));
        };
        if size_bytes == 0 {
            return Err(empty_source(&format!("the object at {key}")));
        }
        if size_bytes > state.config.max_upload_bytes {
            return Err(too_large(state.config.max_upload_bytes));
        }
        None
    };
    Ok(Import {
        key,
        folder,
        filename,
        priority: request.priority,
        batch: batch.map(str::to_owned),
    })
}

/// The keys under `prefix`, checked as an archive's entries would be: some, not too many, one
/// main file among them.
async fn folder_keys(state: &ApiState, prefix: &str) -> ApiResult<Vec<String>> {
    let keys = state.artifacts.list(prefix).await?;
    if keys.is_empty() {
        return Err(ApiError::Unprocessable(format!(
            "no objects under {prefix}/"
        )));
    }
    let max = state.config.archive_limits.max_entries;
    if keys.len() > max {
        return Err(ApiError::Unprocessable(format!(
            "{} objects under {prefix}/, more than the {max} one asset may have",
            keys.len()
        )));
    }
    let files: Vec<Vec<String>> = keys
        .iter()
        .map(|k| relative(prefix, k).split('/').map(str::to_owned).collect())
        .collect();
    uniphys_archive::main_file(&files)
        .map_err(|e| ApiError::Unprocessable(format!("the objects under {prefix}/: {e}")))?;
    Ok(keys)
}

/// `key` relative to `prefix` (a key under it).
fn relative<'k>(prefix: &str, key: &'k str) -> &'k str {
    key.strip_prefix(prefix)
        .map_or(key, |rest| rest.trim_start_matches('/'))
}

/// The object key named by `url`, if it is a well-formed key under one of the tenant's prefixes.
fn object_key(state: &ApiState, tenant: TenantId, url: &str) -> ApiResult<String> {
    if url.contains("://") {
        return Err(ApiError::Unprocessable(format!(
            "url must be an object-store key such as incoming/t{}/cabinet.glb; other URLs are not fetched, got {url:?}",
            tenant.0
        )));
    }
    let key = url.trim_start_matches('/');
    let well_formed = !key.is_empty()
        && key
            .split('/')
            .all(|c| !c.is_empty() && c != "." && c != ".." && !c.chars().any(char::is_control));
    if !well_formed {
        return Err(ApiError::Unprocessable(format!(
            "url must be a key of non-empty components without . or .., got {url:?}"
        )));
    }
    let prefixes: Vec<String> = state
        .config
        .url_prefixes
        .iter()
        .map(|p| p.replace("{tenant}", &tenant.0.to_string()))
        .collect();
    if !prefixes.iter().any(|p| key.starts_with(p.as_str())) {
        return Err(ApiError::Unprocessable(format!(
            "url must name an object under {}, got {url:?}",
            prefixes.join(" or ")
        )));
    }
    Ok(key.to_owned())
}

/// Streams the object to a spool file (hashing it), or packs a prefix's objects into one, and
/// stores and submits it.
async fn run_import(
    state: &ApiState,
    tenant: TenantId,
    import: Import,
) -> ApiResult<(bool, SubmitResponse)> {
    let spooled = match &import.folder {
        Some(keys) => pack_objects(state, &import.key, keys).await?,
        None => {
            let (_, stream) = state.artifacts.get_stream(&import.key).await?;
            spool(
                stream.map_err(ApiError::from),
                state.config.upload_tmp_dir.clone(),
                state.config.max_upload_bytes,
                |e| e,
            )
            .await?
        }
    };
    let placement = Placement {
        priority: import.priority,
        batch: import.batch.as_deref(),
    };
    store_and_submit(state, tenant, spooled, &import.filename, placement).await
}

/// The objects `keys` under `prefix` packed, in order, into a spooled tar (paths relative to
/// the prefix), within the upload cap.
async fn pack_objects(state: &ApiState, prefix: &str, keys: &[String]) -> ApiResult<Spooled> {
    let (file, path) = spool_file(state.config.upload_tmp_dir.clone()).await?;
    let mut tar = DeterministicTar::new(std::io::BufWriter::new(file));
    let max = state.config.max_upload_bytes;
    let mut total = 0u64;
    for key in keys {
        let bytes = state.artifacts.get(key).await?;
        total += bytes.len() as u64;
        if total > max {
            return Err(too_large(max));
        }
        let name = relative(prefix, key).to_owned();
        tar = tokio::task::spawn_blocking(move || {
            tar.append(&name, bytes.len() as u64, bytes.as_slice())
                .map(|()| tar)
        })
        .await
        .map_err(|e| ApiError::Internal(format!("packing task failed: {e}")))?
        .map_err(|e| ApiError::Internal(format!("packing {key} into the spool file: {e}")))?;
    }
    tokio::task::spawn_blocking(move || {
        use std::io::Write;
        tar.finish()?.flush()?;
        digest_file(&path).map(|(sha256_hex, size_bytes)| Spooled {
            path,
            sha256_hex,
            size_bytes,
        })
    })
    .await
    .map_err(|e| ApiError::Internal(format!("packing task failed: {e}")))?
    .map_err(|e| ApiError::Internal(format!("finishing the packed folder: {e}")))
}
