//! What the API asks of the rest of the service (doorbell, live progress, metrics, trace
//! context, readiness of dependencies), as a trait the binary implements, so this crate depends on
//! neither Redis nor the telemetry stack. Every method has a do-nothing default.

use std::collections::BTreeMap;
use std::future::Future;
use std::pin::Pin;
use std::time::Duration;

use axum::http::{HeaderMap, Method};
use serde_json::Value;
use tracing::Span;
use uniphys_queue::JobId;

/// A boxed, sendable future (what the hooks return, so the trait stays object-safe).
pub type BoxFuture<'a, T> = Pin<Box<dyn Future<Output = T> + Send + 'a>>;

/// The body of `GET /metrics`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MetricsText {
    /// Its content type, e.g. `text/plain; version=0.0.4` or
    /// `application/openmetrics-text; version=1.0.0; charset=utf-8`.
    pub content_type: String,
    /// The exposition text.
    pub body: String,
}

/// One dependency checked by `GET /readyz`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadinessCheck {
    /// Its name (`redis`, `object_store`, …).
    pub name: String,
    /// Whether it answered.
    pub ok: bool,
    /// Whether the API is unready without it (Redis is only a hint: not required).
    pub required: bool,
}

/// Service-wide effects of API calls. Implementations must be cheap and must not fail the
/// request: a hint that cannot be delivered is logged by the implementation and dropped.
pub trait ServiceHooks: Send + Sync + 'static {
    /// Runs of these stages became claimable (after a submission or a retry): ring their
    /// doorbells. Names are sorted and unique.
    fn on_stages_ready<'a>(&'a self, stages: &'a [String]) -> BoxFuture<'a, ()> {
        let _ = stages;
        Box::pin(async {})
    }

    /// Live progress of `job`'s running stages, by stage name (e.g. `{"done": 3, "total": 9}`).
    fn progress(&self, job: JobId) -> BoxFuture<'_, BTreeMap<String, Value>> {
        let _ = job;
        Box::pin(async { BTreeMap::new() })
    }

    /// The metrics exposition, or `None` when metrics are off (answered 404).
    fn metrics_text(&self) -> BoxFuture<'_, Option<MetricsText>> {
        Box::pin(async { None })
    }

    /// The W3C `traceparent` of the current span, recorded on submitted jobs so their stages
    /// join the request's trace.
    fn current_traceparent(&self) -> Option<String> {
        None
    }

    /// Dependencies besides the queue database, checked by `GET /readyz`.
    fn readiness(&self) -> BoxFuture<'_, Vec<ReadinessCheck>> {
        Box::pin(async { Vec::new() })
    }

    /// The span of one request (method, route template, headers), e.g. one that joins the
    /// caller's trace from its `traceparent` header; `None` for the API's own `http_request`
    /// span. The API records `http.response.status_code` on it when the response is known.
    fn request_span(&self, method: &Method, route: &str, headers: &HeaderMap) -> Option<Span> {
        let _ = (method, route, headers);
        None
    }

    /// One HTTP request finished: its route template (`/v1/jobs/{job_id}`), method, status and
    /// duration (for request metrics).
    fn observe_request(&self, method: &str, route: &str, status: u16, elapsed: Duration) {
        let _ = (method, route, status, elapsed);
    }
}

/// Hooks that do nothing: no doorbell, no progress, no metrics, no trace context.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoHooks;

impl ServiceHooks for NoHooks {}
