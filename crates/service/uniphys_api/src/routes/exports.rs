//! `POST /v1/batches/{batch}/export` (write the batch as a UniPhys-40K dataset into the object
//! store, in the background) and `GET /v1/batches/{batch}/export` (how that export stands).

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use uniphys_storage::StorageError;

use crate::dataset_export::{DatasetExportView, ExportRegistry, dataset_prefix, summary_key};
use crate::error::{ApiError, ApiResult, ErrorBody};
use crate::extract::{ApiPath, Tenant};
use crate::routes::batches::batch_label;
use crate::state::Shared;

/// Start writing the batch's succeeded assets as a UniPhys-40K dataset under
/// `datasets/t{tenant}/{batch}/` in the object store (entity folders `<type>/<entity>/`,
/// `index.csv`, `failures.csv`, `statistics.json`, then `export.json`). Already-copied files
/// are skipped, so starting it again adds what finished since. An export already running in
/// this process is answered as it stands.
#[utoipa::path(
    post,
    path = "/v1/batches/{batch}/export",
    tag = "assets",
    params(("batch" = String, Path, description = "The batch label")),
    responses(
        (status = 202, description = "The export runs; poll GET for its progress", body = DatasetExportView),
        (status = 400, description = "Malformed label", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "No such batch for this tenant", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn start(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(batch): ApiPath<String>,
) -> ApiResult<(StatusCode, Json<DatasetExportView>)> {
    batch_label(&batch)?;
    if state
        .store
        .batch_job_states(tenant, &batch)
        .await?
        .is_empty()
    {
        return Err(ApiError::NotFound(format!("no batch {batch:?}")));
    }
    let view = ExportRegistry::start(&state, tenant, &batch);
    Ok((StatusCode::ACCEPTED, Json(view)))
}

/// How the batch's export stands: the one this API process runs or ran, else the summary the
/// last finished export left in the object store.
#[utoipa::path(
    get,
    path = "/v1/batches/{batch}/export",
    tag = "assets",
    params(("batch" = String, Path, description = "The batch label")),
    responses(
        (status = 200, description = "The export's progress or summary", body = DatasetExportView),
        (status = 400, description = "Malformed label", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 404, description = "The batch was never exported", body = ErrorBody),
        (status = 503, description = "Object store unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn status(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiPath(batch): ApiPath<String>,
) -> ApiResult<Json<DatasetExportView>> {
    batch_label(&batch)?;
    if let Some(view) = state.exports.get(tenant, &batch) {
        return Ok(Json(view));
    }
    let key = summary_key(&dataset_prefix(tenant, &batch));
    let never = || {
        ApiError::NotFound(format!(
            "batch {batch:?} has not been exported; POST /v1/batches/{batch}/export starts it"
        ))
    };
    let bytes = match state.artifacts.get(&key).await {
        Err(StorageError::NotFound { .. }) => return Err(never()),
        read => read?,
    };
    let view = serde_json::from_slice(&bytes).map_err(|e| {
        ApiError::Unavailable(format!("the export summary {key} cannot be read: {e}"))
    })?;
    Ok(Json(view))
}
