//! The JSON shapes of assets, jobs and stages in answers, and their conversion from the store's
//! types. Ids are in their prefixed form (`asset_12`, `job_7`, `run_40`).

use std::collections::BTreeMap;

use serde::Serialize;
use serde_json::Value;
use uniphys_queue::{AssetInfo, ErrorRecord, JobDetail, StageCost, StageRunInfo, StageState};
use utoipa::ToSchema;

/// An asset: one distinct content of one tenant.
#[derive(Debug, Serialize, ToSchema)]
pub struct AssetView {
    /// `asset_<n>`.
    pub id: String,
    /// `sha256:<hex>` of the content.
    pub content_digest: String,
    /// Object-store key of the content.
    pub source_key: String,
    /// Size of the content.
    pub size_bytes: u64,
    /// Submitted, Unix milliseconds.
    pub created_at_ms: i64,
}

impl From<&AssetInfo> for AssetView {
    fn from(a: &AssetInfo) -> Self {
        Self {
            id: a.id.to_string(),
            content_digest: a.content_digest.clone(),
            source_key: a.source_uri.clone(),
            size_bytes: a.size_bytes,
            created_at_ms: a.created_at_ms,
        }
    }
}

/// A job: one run of the stage graph on an asset, with each stage.
#[derive(Debug, Serialize, ToSchema)]
pub struct JobView {
    /// `job_<n>`.
    pub id: String,
    /// `asset_<n>`.
    pub asset_id: String,
    /// `running`, `succeeded`, `dead` or `cancelled`.
    pub state: String,
    /// Higher runs first.
    pub priority: i32,
    /// Created, Unix milliseconds.
    pub created_at_ms: i64,
    /// Finished, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
    /// The stages, in creation (topological) order.
    pub stages: Vec<StageView>,
}

/// One stage of a job.
#[derive(Debug, Serialize, ToSchema)]
pub struct StageView {
    /// Stage name.
    pub name: String,
    /// `run_<n>`.
    pub run_id: String,
    /// `blocked`, `ready`, `running`, `succeeded`, `dead` or `cancelled`.
    pub state: String,
    /// Attempts made so far (counted at claim).
    pub attempt: u32,
    /// Attempts allowed before dead-lettering.
    pub max_attempts: u32,
    /// Failed attempts, oldest first (kept through retries and dead-lettering).
    pub errors: Vec<ErrorView>,
    /// Claimable from, Unix milliseconds (the end of a retry backoff).
    pub run_after_ms: i64,
    /// Current attempt started, Unix milliseconds.
    pub started_at_ms: Option<i64>,
    /// Finished, Unix milliseconds.
    pub finished_at_ms: Option<i64>,
    /// `finished - started` of a finished attempt, milliseconds.
    pub duration_ms: Option<i64>,
    /// Lease end of a running attempt, Unix milliseconds.
    pub lease_expires_at_ms: Option<i64>,
    /// The worker holding or last holding it.
    pub worker_id: Option<String>,
    /// What it consumed (when succeeded).
    pub cost: Option<CostView>,
    /// The stage's summary from its output manifest (when succeeded).
    #[schema(value_type = Option<Object>)]
    pub summary: Option<Value>,
    /// Live progress reported by the worker; only while the stage runs.
    #[schema(value_type = Option<Object>)]
    pub progress: Option<Value>,
}

/// One failed attempt.
#[derive(Debug, Serialize, ToSchema)]
pub struct ErrorView {
    /// The attempt.
    pub attempt: u32,
    /// `transient`, `permanent` or `lease_expired`.
    pub kind: String,
    /// What happened.
    pub message: String,
    /// The worker that held the attempt.
    pub worker_id: Option<String>,
    /// Recorded, Unix milliseconds.
    pub at_ms: i64,
}

/// What a stage run consumed.
#[derive(Debug, Serialize, ToSchema)]
pub struct CostView {
    /// GPU time, milliseconds.
    pub gpu_ms: u64,
    /// Requests to the LVLM.
    pub lvlm_requests: u64,
    /// LVLM tokens in and out.
    pub lvlm_tokens: u64,
    /// Money spent on external services, millionths of a US dollar.
    pub usd_micros: u64,
}

impl JobView {
    /// The view of `job`, with live `progress` by stage name.
    pub(crate) fn new(job: &JobDetail, progress: &BTreeMap<String, Value>) -> Self {
        Self {
            id: job.id.to_string(),
            asset_id: job.asset_id.to_string(),
            state: job.state.to_string(),
            priority: job.priority,
            created_at_ms: job.created_at_ms,
            finished_at_ms: job.finished_at_ms,
            stages: job
                .stages
                .iter()
                .map(|s| StageView::new(s, progress.get(&s.stage_name).cloned()))
                .collect(),
        }
    }
}

impl StageView {
    fn new(run: &StageRunInfo, progress: Option<Value>) -> Self {
        let summary = run
            .output_manifest
            .as_ref()
            .and_then(uniphys_queue::OutputManifest::from_value)
            .map(|m| m.summary)
            .filter(|s| !s.is_null());
        Self {
            name: run.stage_name.clone(),
            run_id: run.id.to_string(),
            state: run.state.to_string(),
            attempt: run.attempt,
            max_attempts: run.max_attempts,
            errors: run.errors.iter().map(ErrorView::from).collect(),
            run_after_ms: run.run_after_ms,
            started_at_ms: run.started_at_ms,
            finished_at_ms: run.finished_at_ms,
            duration_ms: run
                .started_at_ms
                .zip(run.finished_at_ms)
                .map(|(s, f)| f - s),
            lease_expires_at_ms: run.lease_expires_at_ms,
            worker_id: run.worker_id.as_ref().map(ToString::to_string),
            cost: run.cost.as_ref().map(CostView::from),
            summary,
            // Only a stage that runs now has progress: a finished, waiting or retried one would
            // show its last report ("reading the mesh", half done).
            progress: progress.filter(|_| run.state == StageState::Running),
        }
    }
}

impl From<&ErrorRecord> for ErrorView {
    fn from(e: &ErrorRecord) -> Self {
        let kind = serde_json::to_value(e.kind)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default();
        Self {
            attempt: e.attempt,
            kind,
            message: e.message.clone(),
            worker_id: e.worker_id.clone(),
            at_ms: e.at_ms,
        }
    }
}

impl From<&StageCost> for CostView {
    fn from(c: &StageCost) -> Self {
        Self {
            gpu_ms: c.gpu_ms,
            lvlm_requests: c.lvlm_requests,
            lvlm_tokens: c.lvlm_tokens,
            usd_micros: c.usd_micros,
        }
    }
}

/// The file name at the end of a source key (`sources/t1/<sha>/cabinet.glb` → `cabinet.glb`).
pub(crate) fn file_name(source_key: &str) -> &str {
    source_key.rsplit('/').next().unwrap_or(source_key)
}
