//! `GET /v1/assets/{asset_id}/artifacts` (what the succeeded stages of the latest job wrote) and
//! the streamed download of one of them. Keys come only from the tenant's own manifests, never
//! from the request, so a tenant cannot read another tenant's objects.

use axum::Json;
use axum::body::Body;
use axum::extract::State;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use uniphys_queue::{ArtifactEntry, AssetId, JobDetail, OutputManifest, StageState};
use utoipa::ToSchema;

use super::assets::latest_job;
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{ApiPath, Tenant};
use crate::ids;
use crate::state::Shared;
use crate::upload::content_type_for;

/// One artifact of a succeeded stage.
#[derive(Debug, Serialize, ToSchema)]
pub struct ArtifactView {
    /// The stage that wrote it.
    pub stage: String,
    /// Its name under the stage (`model.urdf`, `meshes/part_1.obj`).
    pub name: String,
    /// `{stage}/{name}`: the `name` to download it by.
    pub path: String,
    /// Size in bytes.
    pub bytes: u64,
    /// Lowercase hex SHA-256 of the content.
    pub sha256: String,
    /// The content type it is served with.
    pub content_type: String,
    /// Its download URL.
    pub href: String,
}

/// The artifacts of an asset's latest job.
#[derive(Debug, Serialize, ToSchema)]
pub struct ArtifactList {
    /// `job_<n>` they come from; absent when the asset has no job.
    pub job_id: Option<String>,
    /// Sorted by stage, then name.
    pub items: Vec<ArtifactView>,
}

/// What the succeeded stages of the asset's latest job wrote.
#[utoipa::path(
    get,
    path = "/v1/assets/{asset_id}/artifacts",
    tag = "artifacts",
    params(("asset_id" = String, Path, description = "`asset_<n>` or `<n>`")),
    responses(
        (status = 200, description = "The artifacts", body = ArtifactList),
        (status = 400, description = "Invalid asset id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such asset for this tenant", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn list(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(raw): ApiPath<String>,
) -> ApiResult<Json<ArtifactList>> {
    let asset_id = ids::asset_id("asset_id", &raw)?;
    state.store.get_asset(tenant, asset_id).await?;
    let Some(job) = latest_job(&state, tenant, asset_id).await? else {
        return Ok(Json(ArtifactList {
            job_id: None,
            items: Vec::new(),
        }));
    };
    let mut items: Vec<ArtifactView> = succeeded_artifacts(&job)
        .map(|(stage, entry)| view(asset_id, stage, &entry))
        .collect();
    items.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(Json(ArtifactList {
        job_id: Some(job.id.to_string()),
        items,
    }))
}

/// Download one artifact, streamed.
#[utoipa::path(
    get,
    path = "/v1/assets/{asset_id}/artifacts/{*name}",
    tag = "artifacts",
    params(
        ("asset_id" = String, Path, description = "`asset_<n>` or `<n>`"),
        ("name" = String, Path, description = "`{stage}/{name}` as listed, e.g. `export/model.urdf`"),
    ),
    responses(
        (status = 200, description = "The artifact's bytes", content_type = "application/octet-stream", body = Vec<u8>),
        (status = 400, description = "Invalid asset id", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such asset for this tenant, or no such artifact", body = ErrorBody),
        (status = 503, description = "Object store unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn download(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath((raw, path)): ApiPath<(String, String)>,
) -> ApiResult<Response> {
    let asset_id = ids::asset_id("asset_id", &raw)?;
    state.store.get_asset(tenant, asset_id).await?;
    let not_found = || ApiError::NotFound(format!("no artifact {path:?} for {asset_id}"));
    let (stage, name) = path.split_once('/').ok_or_else(not_found)?;
    let job = latest_job(&state, tenant, asset_id)
        .await?
        .ok_or_else(not_found)?;
    let entry = succeeded_artifacts(&job)
        .find(|(s, e)| *s == stage && e.name == name)
        .map(|(_, e)| e)
        .ok_or_else(not_found)?;
    let (size, stream) = state.artifacts.get_stream(&entry.key).await?;
    let mut response = (StatusCode::OK, Body::from_stream(stream)).into_response();
    let headers = response.headers_mut();
    headers.insert(header::CONTENT_LENGTH, HeaderValue::from(size));
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static(content_type_for(&entry.name)),
    );
    let basename = entry.name.rsplit('/').next().unwrap_or_default();
    if let Ok(v) = HeaderValue::from_str(&format!("attachment; filename=\"{basename}\"")) {
        headers.insert(header::CONTENT_DISPOSITION, v);
    }
    if let Ok(v) = HeaderValue::from_str(&format!("\"{}\"", entry.sha256)) {
        headers.insert(header::ETAG, v);
    }
    Ok(response)
}

/// The artifacts of `job`'s succeeded stages, with their stage names.
pub(crate) fn succeeded_artifacts(job: &JobDetail) -> impl Iterator<Item = (&str, ArtifactEntry)> {
    job.stages
        .iter()
        .filter(|run| run.state == StageState::Succeeded)
        .filter_map(|run| {
            let manifest = run
                .output_manifest
                .as_ref()
                .and_then(OutputManifest::from_value)?;
            Some((run.stage_name.as_str(), manifest))
        })
        .flat_map(|(stage, manifest)| manifest.artifacts.into_iter().map(move |a| (stage, a)))
}

fn view(asset_id: AssetId, stage: &str, entry: &ArtifactEntry) -> ArtifactView {
    let path = format!("{stage}/{}", entry.name);
    ArtifactView {
        stage: stage.to_owned(),
        name: entry.name.clone(),
        href: format!("/v1/assets/{asset_id}/artifacts/{path}"),
        path,
        bytes: entry.bytes,
        sha256: entry.sha256.clone(),
        content_type: content_type_for(&entry.name).to_owned(),
    }
}
