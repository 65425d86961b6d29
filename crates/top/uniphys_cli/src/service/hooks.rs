//! What the API asks of the rest of the service: doorbells, live progress, metrics, the trace
//! context of a request, readiness of Redis.

use std::collections::BTreeMap;
use std::time::Duration;

use serde_json::{Value, json};
use uniphys_api::{BoxFuture, MetricsText, ReadinessCheck, ServiceHooks};
use uniphys_hints::Hints;
use uniphys_queue::{JobId, QueueStore};
use uniphys_telemetry::Metrics;

/// The service's hooks: Redis (or in-process) hints, Prometheus metrics, OpenTelemetry context.
pub struct Hooks {
    pub hints: Hints,
    pub metrics: Metrics,
    pub store: QueueStore,
    /// Whether Redis is configured (then it is a readiness check, not required).
    pub redis: bool,
}

impl ServiceHooks for Hooks {
    fn on_stages_ready<'a>(&'a self, stages: &'a [String]) -> BoxFuture<'a, ()> {
        Box::pin(async move {
            for stage in stages {
                if self.hints.ring(stage).await.is_err() {
                    self.metrics.record_hints_error("ring");
                }
            }
        })
    }

    fn progress(&self, job: JobId) -> BoxFuture<'_, BTreeMap<String, Value>> {
        Box::pin(async move {
            match self.hints.progress(job.0).await {
                Ok(map) => map
                    .into_iter()
                    .map(|(stage, p)| {
                        (
                            stage,
                            json!({ "fraction": p.fraction, "message": p.message }),
                        )
                    })
                    .collect(),
                Err(_) => {
                    self.metrics.record_hints_error("progress");
                    BTreeMap::new()
                }
            }
        })
    }

    fn metrics_text(&self) -> BoxFuture<'_, Option<MetricsText>> {
        Box::pin(async move {
            // Gauges are read from the store at scrape time; a failed read keeps the last values.
            let _ = self
                .metrics
                .refresh_queue_gauges(&self.store, Duration::from_secs(300))
                .await;
            Some(MetricsText {
                content_type: Metrics::CONTENT_TYPE.into(),
                body: self.metrics.encode(),
            })
        })
    }

    fn request_span(
        &self,
        method: &axum::http::Method,
        route: &str,
        headers: &axum::http::HeaderMap,
    ) -> Option<tracing::Span> {
        Some(uniphys_telemetry::http_request_span(method, route, headers))
    }

    fn current_traceparent(&self) -> Option<String> {
        uniphys_telemetry::current_traceparent()
    }

    fn readiness(&self) -> BoxFuture<'_, Vec<ReadinessCheck>> {
        Box::pin(async move {
            if !self.redis {
                return Vec::new();
            }
            vec![ReadinessCheck {
                name: "redis".into(),
                ok: self.hints.ping().await.is_ok(),
                // Work goes on by polling without Redis: it is not required.
                required: false,
            }]
        })
    }

    fn observe_request(&self, method: &str, route: &str, status: u16, elapsed: Duration) {
        self.metrics
            .record_http_request(method, route, status, elapsed);
    }
}
