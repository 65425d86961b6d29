//! A batch written as a UniPhys-40K dataset into the object store, under
//! `datasets/t{tenant}/{batch}/` (the layout of [`crate::dataset_layout`]): each succeeded
//! asset's convert files copied to `<type>/<entity>/`, then `index.csv`, `failures.csv`,
//! `statistics.json` and, last, `export.json` (this export's counts; its presence says the
//! tables are complete).
//!
//! It runs as a task of the API process that started it; [`ExportRegistry`] holds its progress.
//! Copies are create-only and skipped when already there, so an export run again (after a crash,
//! or when more of the batch has finished) copies only what is new. The UniPhysGen npz inputs
//! need the pipeline's point sampler and are not written here (`uniphys dataset export` writes
//! them into a folder).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use serde::{Deserialize, Serialize};
use serde_json::Value;
use uniphys_queue::{ArtifactEntry, JobDetail, JobFilter, JobState, TenantId};
use utoipa::ToSchema;

use crate::board::now_ms;
use crate::dataset_layout::{
    self as layout, ENTITY_STAGE, FAILURE_COLUMNS, INDEX_COLUMNS, IndexEntry,
};
use crate::error::{ApiError, ApiResult};
use crate::routes::artifacts::succeeded_artifacts;
use crate::routes::batches::compute_stats;
use crate::state::Shared;

/// Jobs read per page of the batch.
const PAGE: u32 = 1000;

/// Where a batch's dataset is written in the object store.
#[must_use]
pub(crate) fn dataset_prefix(tenant: TenantId, batch: &str) -> String {
    format!("datasets/t{}/{batch}/", tenant.0)
}

/// The key of an export's summary, written when it finishes.
pub(crate) fn summary_key(prefix: &str) -> String {
    format!("{prefix}export.json")
}

/// An export of a batch into the object store: where it is and what it has done.
#[derive(Clone, Debug, Serialize, Deserialize, ToSchema)]
pub struct DatasetExportView {
    /// The batch.
    pub batch: String,
    /// Where the dataset is written in the object store (`datasets/t{tenant}/{batch}/`).
    pub prefix: String,
    /// `running`, `finished` or `failed`.
    pub state: String,
    /// Jobs of the batch read so far.
    pub jobs_read: u64,
    /// Entities copied by this export.
    pub exported: u64,
    /// Entities a previous export had already copied whole.
    pub already_there: u64,
    /// Jobs still running: run the export again once they finish.
    pub still_running: u64,
    /// Dead or cancelled jobs, and succeeded ones whose files could not be placed or that have
    /// none (`failures.csv`).
    pub failed: u64,
    /// Why the export stopped, when it failed.
    pub error: Option<String>,
    /// When it started, Unix milliseconds.
    pub started_at_ms: i64,
    /// When it finished or failed, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
}

/// One export's progress, shared by its task and the handlers.
type Progress = Arc<Mutex<DatasetExportView>>;

/// The exports this API process runs or ran, by tenant and batch.
#[derive(Debug, Default)]
pub(crate) struct ExportRegistry {
    exports: Mutex<HashMap<(TenantId, String), Progress>>,
}

impl ExportRegistry {
    /// The export of `batch` this process knows, running or ended.
    pub(crate) fn get(&self, tenant: TenantId, batch: &str) -> Option<DatasetExportView> {
        let exports = self.exports.lock().unwrap_or_else(PoisonError::into_inner);
        exports
            .get(&(tenant, batch.to_owned()))
            .map(|p| lock(p).clone())
    }

    /// Starts exporting `batch` unless this process is already doing it; returns its progress.
    pub(crate) fn start(state: &Shared, tenant: TenantId, batch: &str) -> DatasetExportView {
        let mut exports = state
            .exports
            .exports
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let key = (tenant, batch.to_owned());
        if let Some(running) = exports.get(&key) {
            let view = lock(running).clone();
            if view.state == "running" {
                return view;
            }
        }
        let view = DatasetExportView {
            batch: batch.to_owned(),
            prefix: dataset_prefix(tenant, batch),
            state: "running".into(),
            jobs_read: 0,
            exported: 0,
            already_there: 0,
            still_running: 0,
            failed: 0,
            error: None,
            started_at_ms: now_ms(),
            finished_at_ms: None,
        };
        let progress = Arc::new(Mutex::new(view.clone()));
        exports.insert(key, progress.clone());
        tokio::spawn(run(state.clone(), tenant, batch.to_owned(), progress));
        view
    }
}

fn lock(progress: &Mutex<DatasetExportView>) -> std::sync::MutexGuard<'_, DatasetExportView> {
    progress.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Runs the export to its end and records how it ended (the summary object when it finished,
/// the error in the progress when it failed).
async fn run(state: Shared, tenant: TenantId, batch: String, progress: Progress) {
    let outcome = match export_batch(&state, tenant, &batch, &progress).await {
        Ok(()) => {
            let mut view = lock(&progress).clone();
            view.state = "finished".into();
            view.finished_at_ms = Some(now_ms());
            let bytes = serde_json::to_vec_pretty(&view).unwrap_or_default();
            state
                .artifacts
                .put(&summary_key(&view.prefix), bytes)
                .await
                .map_err(ApiError::from)
        }
        Err(e) => Err(e),
    };
    let mut view = lock(&progress);
    view.finished_at_ms = Some(now_ms());
    match outcome {
        Ok(()) => view.state = "finished".into(),
        Err(e) => {
            tracing::warn!(batch = %batch, error = %e, "dataset export failed");
            view.state = "failed".into();
            view.error = Some(e.to_string());
        }
    }
}

/// Copies every succeeded asset's entity and writes the tables.
async fn export_batch(
    state: &Shared,
    tenant: TenantId,
    batch: &str,
    progress: &Mutex<DatasetExportView>,
) -> ApiResult<()> {
    let prefix = dataset_prefix(tenant, batch);
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let mut filter = JobFilter {
        batch: Some(batch.to_owned()),
        limit: PAGE,
        ..JobFilter::default()
    };
    loop {
        let jobs = state.store.list_jobs(tenant, &filter).await?;
        for job in &jobs {
            let file = crate::views::file_name(&job.source_uri);
            let (asset, job_id) = (job.asset_id.to_string(), job.id.to_string());
            let failure = |state: &str, stage: &str, error: &str| {
                [&asset, &job_id, file, state, stage, error]
                    .map(ToString::to_string)
                    .to_vec()
            };
            match job.state {
                JobState::Running => lock(progress).still_running += 1,
                JobState::Succeeded => {
                    let detail = state.store.get_job(tenant, job.id).await?;
                    match export_entity(state, &prefix, &detail, file).await {
                        Ok(Some((row, copied))) => {
                            rows.push(row);
                            let mut view = lock(progress);
                            if copied {
                                view.exported += 1;
                            } else {
                                view.already_there += 1;
                            }
                        }
                        Ok(None) => {
                            failures.push(failure(
                                "succeeded",
                                ENTITY_STAGE,
                                "the job succeeded but its convert stage wrote no files",
                            ));
                            lock(progress).failed += 1;
                        }
                        // One asset whose files cannot be placed (other bytes already there, or
                        // its artifacts gone) is listed, not fatal.
                        Err(ApiError::Conflict(why) | ApiError::NotFound(why)) => {
                            failures.push(failure("succeeded", ENTITY_STAGE, &why));
                            lock(progress).failed += 1;
                        }
                        Err(e) => return Err(e),
                    }
                }
                JobState::Dead | JobState::Cancelled => {
                    let detail = state.store.get_job(tenant, job.id).await?;
                    let stopped = detail.stages.iter().find(|s| {
                        matches!(
                            s.state,
                            uniphys_queue::StageState::Dead | uniphys_queue::StageState::Cancelled
                        )
                    });
                    let stage = stopped.map_or("", |s| s.stage_name.as_str());
                    let error = stopped
                        .and_then(|s| s.errors.last())
                        .map_or("", |e| e.message.as_str());
                    failures.push(failure(job.state.as_str(), stage, error));
                    lock(progress).failed += 1;
                }
            }
            lock(progress).jobs_read += 1;
        }
        match jobs.last() {
            Some(last) if jobs.len() == PAGE as usize => filter.before = Some(last.id),
            _ => break,
        }
    }
    rows.sort();
    failures.sort();
    let put = |name: &str, bytes: Vec<u8>| {
        let key = format!("{prefix}{name}");
        async move { state.artifacts.put(&key, bytes).await }
    };
    put(
        "index.csv",
        layout::csv_text(INDEX_COLUMNS, &rows).into_bytes(),
    )
    .await?;
    put(
        "failures.csv",
        layout::csv_text(FAILURE_COLUMNS, &failures).into_bytes(),
    )
    .await?;
    let statistics = compute_stats(state, tenant, batch.to_owned()).await?;
    let statistics = serde_json::to_vec_pretty(&statistics)
        .map_err(|e| ApiError::Unavailable(format!("cannot encode the statistics: {e}")))?;
    put("statistics.json", statistics).await?;
    Ok(())
}

/// Copies a succeeded job's convert files to `<prefix><type>/<entity>/`, each unless already
/// there whole; returns its index row and whether anything was copied, or `None` when the
/// convert stage wrote nothing.
async fn export_entity(
    state: &Shared,
    prefix: &str,
    job: &JobDetail,
    file: &str,
) -> ApiResult<Option<(Vec<String>, bool)>> {
    let files: Vec<ArtifactEntry> = succeeded_artifacts(job)
        .filter(|(stage, _)| *stage == ENTITY_STAGE)
        .map(|(_, entry)| entry)
        .collect();
    if files.is_empty() {
        return Ok(None);
    }
    let read_json = |name: &str| {
        let key = files.iter().find(|e| e.name == name).map(|e| e.key.clone());
        async move {
            let Some(key) = key else {
                return Ok(Value::Null);
            };
            let bytes = state.artifacts.get(&key).await?;
            Ok::<Value, ApiError>(serde_json::from_slice(&bytes).unwrap_or(Value::Null))
        }
    };
    let object = read_json("annotations/object.json").await?;
    let kind = layout::type_name(object["category"].as_str().unwrap_or_default());
    let (asset, job_id) = (job.asset_id.to_string(), job.id.to_string());
    let place = format!("{kind}/{}", layout::entity_name(file, &asset));
    let mut copied = false;
    for entry in &files {
        let dest = format!("{prefix}{place}/{}", entry.name);
        // Copies are create-only and whole, and only exports write under `datasets/`, so a file
        // of the listed size is this one (not read again: a resumed export stays cheap).
        if state.artifacts.head(&dest).await? == Some(entry.bytes) {
            continue;
        }
        let bytes = state.artifacts.get(&entry.key).await?;
        state.artifacts.put_once(&dest, bytes).await?;
        copied = true;
    }
    let record = read_json("record.json").await?;
    let report = read_json("report.json").await?;
    let row = layout::index_row(&IndexEntry {
        place: &place,
        asset: &asset,
        job: &job_id,
        source_file: file,
        record: &record,
        report: &report,
        npz_files: 0,
    });
    Ok(Some((row, copied)))
}
