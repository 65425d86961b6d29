//! `GET /v1/overview`: what the dashboard polls. The queue's statistics per stage (shared by
//! every viewer and recomputed at most once per `board_refresh`), the caller's jobs by state, and
//! the history samples newer than `since_ms`.

use axum::Json;
use axum::extract::State;
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{ApiQuery, Tenant};
use crate::routes::ops::StageStatsView;
use crate::state::Shared;

/// Which history samples to send.
#[derive(Debug, Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
#[into_params(parameter_in = Query)]
pub(crate) struct OverviewParams {
    /// Only samples taken after this time, Unix milliseconds (the last `at_ms` the caller has);
    /// default: the whole history.
    since_ms: Option<i64>,
}

/// The dashboard's overview.
#[derive(Debug, Serialize, ToSchema)]
pub struct OverviewResponse {
    /// When the statistics were computed, Unix milliseconds (server clock).
    pub generated_at_ms: i64,
    /// The caller's tenant.
    pub tenant: TenantOverview,
    /// The window of the `*_in_window` counts and the throughput, seconds.
    pub window_secs: u64,
    /// Every stage of the queue (all tenants), as `GET /v1/stats` answers.
    pub stages: Vec<StageStatsView>,
    /// Samples over time.
    pub history: HistoryView,
}

/// The caller's tenant and its jobs.
#[derive(Debug, Serialize, ToSchema)]
pub struct TenantOverview {
    /// `tenant_<n>`.
    pub id: String,
    /// Its jobs by state.
    pub jobs: JobCounts,
}

/// Jobs counted by state.
#[derive(Clone, Debug, Default, Serialize, ToSchema)]
pub struct JobCounts {
    /// Some stage still has work to do.
    pub running: u64,
    /// Every stage succeeded.
    pub succeeded: u64,
    /// A stage was dead-lettered.
    pub dead: u64,
    /// Cancelled.
    pub cancelled: u64,
}

impl JobCounts {
    pub(crate) fn from_states(
        counts: impl IntoIterator<Item = (uniphys_queue::JobState, u64)>,
    ) -> Self {
        use uniphys_queue::JobState;
        let mut out = Self::default();
        for (state, n) in counts {
            match state {
                JobState::Running => out.running += n,
                JobState::Succeeded => out.succeeded += n,
                JobState::Dead => out.dead += n,
                JobState::Cancelled => out.cancelled += n,
            }
        }
        out
    }

    /// All jobs.
    pub(crate) fn total(&self) -> u64 {
        self.running + self.succeeded + self.dead + self.cancelled
    }
}

/// The history of the queue's statistics.
#[derive(Debug, Serialize, ToSchema)]
pub struct HistoryView {
    /// Time between samples, seconds.
    pub interval_secs: f64,
    /// Samples, oldest first.
    pub samples: Vec<SampleView>,
}

/// Every stage at one moment.
#[derive(Debug, Serialize, ToSchema)]
pub struct SampleView {
    /// Taken at, Unix milliseconds.
    pub at_ms: i64,
    /// Per stage.
    pub stages: Vec<StagePointView>,
}

/// One stage at one moment.
#[derive(Debug, Serialize, ToSchema)]
pub struct StagePointView {
    /// Stage name.
    pub stage: String,
    /// Runs waiting for a worker (claimable plus backing off).
    pub depth: u64,
    /// Leased by a worker.
    pub running: u64,
    /// Dead-lettered.
    pub failed: u64,
    /// Successes per second over the statistics window.
    pub throughput_per_sec: f64,
}

/// The dashboard's overview: statistics per stage, the caller's jobs by state, the history.
#[utoipa::path(
    get,
    path = "/v1/overview",
    tag = "operations",
    params(OverviewParams),
    responses(
        (status = 200, description = "The overview", body = OverviewResponse),
        (status = 400, description = "Unknown parameter or a bad since_ms", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn overview(
    State(state): State<Shared>,
    Tenant(tenant): Tenant,
    ApiQuery(params): ApiQuery<OverviewParams>,
) -> ApiResult<Json<OverviewResponse>> {
    let config = &state.config;
    let snapshot = state
        .board
        .snapshot(&state.store, config.stats_window, config.board_refresh)
        .await?;
    let jobs = state
        .board
        .tenant_jobs(&state.store, tenant, config.board_refresh)
        .await?;
    let samples = state
        .board
        .history_since(params.since_ms.unwrap_or(i64::MIN))
        .into_iter()
        .map(|s| SampleView {
            at_ms: s.at_ms,
            stages: s
                .stages
                .into_iter()
                .map(|p| StagePointView {
                    stage: p.stage,
                    depth: p.depth,
                    running: p.running,
                    failed: p.failed,
                    throughput_per_sec: p.throughput_per_sec,
                })
                .collect(),
        })
        .collect();
    Ok(Json(OverviewResponse {
        generated_at_ms: snapshot.at_ms,
        tenant: TenantOverview {
            id: tenant.to_string(),
            jobs: JobCounts::from_states(jobs.iter().copied()),
        },
        window_secs: config.stats_window.as_secs(),
        stages: snapshot.stages.iter().map(StageStatsView::from).collect(),
        history: HistoryView {
            interval_secs: config.history_interval.as_secs_f64(),
            samples,
        },
    }))
}
