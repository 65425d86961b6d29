//! Operating the service: queue statistics, liveness, readiness, metrics and the OpenAPI document.

use std::sync::Arc;

use axum::extract::State;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::{Extension, Json};
use serde::Serialize;
use uniphys_queue::StageStats;
use utoipa::ToSchema;

use crate::error::{ApiError, ApiResult, ErrorBody, UNAVAILABLE_RETRY_AFTER_SECS, error_chain};
use crate::extract::Tenant;
use crate::state::Shared;

/// Queue statistics of one stage (all tenants).
#[derive(Debug, Serialize, ToSchema)]
pub struct StageStatsView {
    /// Stage name.
    pub stage: String,
    /// Whether claims of the stage are paused.
    pub paused: bool,
    /// Runs waiting for a worker: claimable now plus backing off before a retry.
    pub depth: u64,
    /// Claimable now.
    pub ready: u64,
    /// Waiting for a retry backoff to end.
    pub backing_off: u64,
    /// Waiting for upstream stages.
    pub blocked: u64,
    /// Leased by a worker.
    pub running: u64,
    /// Dead-lettered (failed for good), awaiting a retry or cancel.
    pub failed: u64,
    /// Succeeded within the window.
    pub succeeded_in_window: u64,
    /// Attempts failed within the window.
    pub failed_in_window: u64,
    /// Successes per second over the window.
    pub throughput_per_sec: f64,
    /// How long the oldest claimable run has waited, milliseconds.
    pub oldest_waiting_age_ms: u64,
    /// No worker serves the stage: its work has been claimable for the whole window and none
    /// was leased or finished. Start a worker whose `UNIPHYS_STAGES` includes it.
    pub unserved: bool,
}

impl From<&StageStats> for StageStatsView {
    fn from(s: &StageStats) -> Self {
        Self {
            stage: s.stage_name.clone(),
            paused: s.paused,
            depth: s.ready + s.backing_off,
            ready: s.ready,
            backing_off: s.backing_off,
            blocked: s.blocked,
            running: s.running,
            failed: s.dead,
            succeeded_in_window: s.succeeded_in_window,
            failed_in_window: s.failed_in_window,
            throughput_per_sec: s.throughput_per_sec(),
            oldest_waiting_age_ms: s.oldest_ready_age_ms,
            unserved: s.unserved(),
        }
    }
}

/// Queue statistics per stage.
#[derive(Debug, Serialize, ToSchema)]
pub struct StatsResponse {
    /// The window of the `*_in_window` counts and the throughput, seconds.
    pub window_secs: u64,
    /// By stage name.
    pub stages: Vec<StageStatsView>,
}

/// Liveness.
#[derive(Debug, Serialize, ToSchema)]
pub struct HealthResponse {
    /// Always `ok`.
    pub status: String,
}

/// Readiness and what it was judged on.
#[derive(Debug, Serialize, ToSchema)]
pub struct ReadyResponse {
    /// Whether every required dependency answered.
    pub ready: bool,
    /// Each dependency checked.
    pub checks: Vec<CheckView>,
}

/// One dependency checked for readiness.
#[derive(Debug, Serialize, ToSchema)]
pub struct CheckView {
    /// `database`, `redis`, …
    pub name: String,
    /// Whether it answered.
    pub ok: bool,
    /// Whether readiness requires it.
    pub required: bool,
}

/// The OpenAPI document as served.
#[derive(Clone, Debug)]
pub(crate) struct OpenApiJson(pub Arc<String>);

/// Queue statistics per stage: depth, running, failed, throughput, oldest waiting age.
#[utoipa::path(
    get,
    path = "/v1/stats",
    tag = "operations",
    responses(
        (status = 200, description = "Statistics per stage", body = StatsResponse),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 503, description = "Database unavailable; see Retry-After", body = ErrorBody),
    ),
    security(("api_key" = []))
)]
pub(crate) async fn stats(
    State(state): State<Shared>,
    Tenant(_): Tenant,
) -> ApiResult<Json<StatsResponse>> {
    let window = state.config.stats_window;
    let stages = state
        .store
        .stage_stats(window)
        .await?
        .iter()
        .map(StageStatsView::from)
        .collect();
    Ok(Json(StatsResponse {
        window_secs: window.as_secs(),
        stages,
    }))
}

/// Liveness: the process answers.
#[utoipa::path(
    get,
    path = "/healthz",
    tag = "operations",
    responses((status = 200, description = "The process is up", body = HealthResponse))
)]
pub(crate) async fn healthz() -> Json<HealthResponse> {
    Json(HealthResponse {
        status: "ok".into(),
    })
}

/// Readiness: the queue database answers, and so does every required dependency.
#[utoipa::path(
    get,
    path = "/readyz",
    tag = "operations",
    responses(
        (status = 200, description = "Ready", body = ReadyResponse),
        (status = 503, description = "A required dependency is down; see Retry-After", body = ReadyResponse),
    )
)]
pub(crate) async fn readyz(State(state): State<Shared>) -> Response {
    let database_ok = match state.store.paused_stages().await {
        Ok(_) => true,
        Err(e) => {
            tracing::warn!(error = %error_chain(&e), "readiness: database does not answer");
            false
        }
    };
    let mut checks = vec![CheckView {
        name: "database".into(),
        ok: database_ok,
        required: true,
    }];
    checks.extend(
        state
            .hooks
            .readiness()
            .await
            .into_iter()
            .map(|c| CheckView {
                name: c.name,
                ok: c.ok,
                required: c.required,
            }),
    );
    let ready = checks.iter().all(|c| c.ok || !c.required);
    let status = if ready {
        StatusCode::OK
    } else {
        StatusCode::SERVICE_UNAVAILABLE
    };
    let mut response = (status, Json(ReadyResponse { ready, checks })).into_response();
    if !ready {
        response.headers_mut().insert(
            header::RETRY_AFTER,
            HeaderValue::from(UNAVAILABLE_RETRY_AFTER_SECS),
        );
    }
    response
}

/// Prometheus metrics (text exposition or OpenMetrics, as the telemetry layer encodes them).
#[utoipa::path(
    get,
    path = "/metrics",
    tag = "operations",
    responses(
        (status = 200, description = "The metrics", content_type = "text/plain", body = String),
        (status = 404, description = "Metrics are not enabled", body = ErrorBody),
    )
)]
pub(crate) async fn metrics(State(state): State<Shared>) -> ApiResult<Response> {
    let Some(metrics) = state.hooks.metrics_text().await else {
        return Err(ApiError::NotFound("metrics are not enabled".into()));
    };
    let content_type = HeaderValue::from_str(&metrics.content_type)
        .unwrap_or_else(|_| HeaderValue::from_static("text/plain; version=0.0.4"));
    Ok(([(header::CONTENT_TYPE, content_type)], metrics.body).into_response())
}

/// This document.
#[utoipa::path(
    get,
    path = "/openapi.json",
    tag = "operations",
    responses((status = 200, description = "The OpenAPI document", content_type = "application/json", body = Object))
)]
pub(crate) async fn openapi(Extension(doc): Extension<OpenApiJson>) -> Response {
    (
        [(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/json"),
        )],
        doc.0.as_str().to_owned(),
    )
        .into_response()
}
