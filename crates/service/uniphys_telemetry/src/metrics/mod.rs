//! Prometheus metrics of the service: queue depth and age, claims, stage runs, table health,
//! HTTP requests and Redis hint errors, rendered as OpenMetrics text for `/metrics`.

mod labels;
mod refresh;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::metrics::histogram::Histogram;
use prometheus_client::registry::{Registry, Unit};

pub use labels::StageOutcome;
use labels::{
    HttpLabels, HttpRouteLabels, OpLabels, StageLabels, StageOutcomeLabels, StageStateLabels,
    TableLabels,
};

/// Claim round trips: 1 ms to 10 s.
const CLAIM_SECONDS_BUCKETS: [f64; 12] = [
    0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 10.0,
];

/// Stage attempts: 10 ms to 1 h.
const STAGE_SECONDS_BUCKETS: [f64; 18] = [
    0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0, 60.0, 120.0, 300.0, 600.0,
    1200.0, 1800.0, 3600.0,
];

/// Attempt numbers: 1 to 10.
const ATTEMPT_BUCKETS: [f64; 7] = [1.0, 2.0, 3.0, 4.0, 5.0, 7.0, 10.0];

/// HTTP requests: 1 ms to 30 s (uploads are the slow ones).
const HTTP_SECONDS_BUCKETS: [f64; 13] = [
    0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 10.0, 30.0,
];

type Histograms<L> = Family<L, Histogram, fn() -> Histogram>;
type FloatGauge = Gauge<f64, std::sync::atomic::AtomicU64>;

fn claim_histogram() -> Histogram {
    Histogram::new(CLAIM_SECONDS_BUCKETS)
}

fn stage_histogram() -> Histogram {
    Histogram::new(STAGE_SECONDS_BUCKETS)
}

fn attempt_histogram() -> Histogram {
    Histogram::new(ATTEMPT_BUCKETS)
}

fn http_histogram() -> Histogram {
    Histogram::new(HTTP_SECONDS_BUCKETS)
}

/// Every metric family of the service, with its registry. Cheap to clone (shared inside);
/// one per process, handed to the HTTP layer, the worker loop and the gauge refresher.
#[derive(Clone, Debug)]
pub struct Metrics {
    inner: Arc<Inner>,
}

#[derive(Debug)]
struct Inner {
    registry: Registry,
    queue_depth: Family<StageStateLabels, Gauge>,
    queue_oldest_ready_age: Family<StageLabels, FloatGauge>,
    claim_latency: Histograms<StageLabels>,
    stage_duration: Histograms<StageOutcomeLabels>,
    stage_attempts: Histograms<StageLabels>,
    stage_runs: Family<StageOutcomeLabels, Counter>,
    table_dead_tuples: Family<TableLabels, Gauge>,
    table_live_tuples: Family<TableLabels, Gauge>,
    http_requests: Family<HttpLabels, Counter>,
    http_request_duration: Histograms<HttpRouteLabels>,
    hints_errors: Family<OpLabels, Counter>,
    /// Serialises gauge refreshes (each clears and refills its families) with encoding.
    refresh: Mutex<()>,
}

impl Default for Metrics {
    fn default() -> Self {
        Self::new()
    }
}

impl Metrics {
    /// All families registered, none with a series yet.
    #[must_use]
    pub fn new() -> Self {
        let mut registry = Registry::default();
        let queue_depth = Family::default();
        registry.register(
            "uniphys_queue_depth",
            "Stage runs by stage and state (blocked, ready, backing_off, running, dead)",
            queue_depth.clone(),
        );
        let queue_oldest_ready_age = Family::default();
        registry.register_with_unit(
            "uniphys_queue_oldest_ready_age",
            "How long the oldest claimable run of a stage has waited",
            Unit::Seconds,
            queue_oldest_ready_age.clone(),
        );
        let claim_latency: Histograms<StageLabels> = Family::new_with_constructor(claim_histogram);
        registry.register_with_unit(
            "uniphys_claim_latency",
            "Duration of a worker's claim call (database round trip)",
            Unit::Seconds,
            claim_latency.clone(),
        );
        let stage_duration: Histograms<StageOutcomeLabels> =
            Family::new_with_constructor(stage_histogram);
        registry.register_with_unit(
            "uniphys_stage_duration",
            "Wall time of one stage attempt, by how it ended",
            Unit::Seconds,
            stage_duration.clone(),
        );
        let stage_attempts: Histograms<StageLabels> =
            Family::new_with_constructor(attempt_histogram);
        registry.register(
            "uniphys_stage_attempts",
            "Attempt number of each finished stage attempt (1 = first try)",
            stage_attempts.clone(),
        );
        let stage_runs = Family::default();
        registry.register(
            "uniphys_stage_runs",
            "Finished stage attempts, by how they ended",
            stage_runs.clone(),
        );
        let table_dead_tuples = Family::default();
        registry.register(
            "uniphys_table_dead_tuples",
            "Dead rows not yet vacuumed in a queue table (Postgres estimate)",
            table_dead_tuples.clone(),
        );
        let table_live_tuples = Family::default();
        registry.register(
            "uniphys_table_live_tuples",
            "Live rows in a queue table (Postgres estimate)",
            table_live_tuples.clone(),
        );
        let http_requests = Family::default();
        registry.register(
            "uniphys_http_requests",
            "HTTP requests answered, by method, matched route and status",
            http_requests.clone(),
        );
        let http_request_duration: Histograms<HttpRouteLabels> =
            Family::new_with_constructor(http_histogram);
        registry.register_with_unit(
            "uniphys_http_request_duration",
            "Time to answer an HTTP request, by method and matched route",
            Unit::Seconds,
            http_request_duration.clone(),
        );
        let hints_errors = Family::default();
        registry.register(
            "uniphys_hints_errors",
            "Failed Redis hint operations (the queue works on without them)",
            hints_errors.clone(),
        );
        Self {
            inner: Arc::new(Inner {
                registry,
                queue_depth,
                queue_oldest_ready_age,
                claim_latency,
                stage_duration,
                stage_attempts,
                stage_runs,
                table_dead_tuples,
                table_live_tuples,
                http_requests,
                http_request_duration,
                hints_errors,
                refresh: Mutex::new(()),
            }),
        }
    }

    /// Records how long a claim call for `stage` took. A worker claiming several stages at once
    /// passes one label for the call (for example the stages joined with `,`).
    pub fn observe_claim_latency(&self, stage: &str, elapsed: Duration) {
        self.inner
            .claim_latency
            .get_or_create(&stage_labels(stage))
            .observe(elapsed.as_secs_f64());
    }

    /// Records one finished attempt of a `stage` run: its wall time and outcome, and which
    /// attempt it was.
    pub fn record_stage_attempt(
        &self,
        stage: &str,
        outcome: StageOutcome,
        attempt: u32,
        elapsed: Duration,
    ) {
        let labels = StageOutcomeLabels {
            stage: stage.to_owned(),
            outcome: outcome.as_str(),
        };
        self.inner
            .stage_duration
            .get_or_create(&labels)
            .observe(elapsed.as_secs_f64());
        self.inner.stage_runs.get_or_create(&labels).inc();
        self.inner
            .stage_attempts
            .get_or_create(&stage_labels(stage))
            .observe(f64::from(attempt));
    }

    /// Records one answered HTTP request; `route` is the matched route template
    /// (`/v1/jobs/{id}`), never the raw path, to keep the label set small.
    pub fn record_http_request(&self, method: &str, route: &str, status: u16, elapsed: Duration) {
        self.inner
            .http_requests
            .get_or_create(&HttpLabels {
                method: method.to_owned(),
                route: route.to_owned(),
                status,
            })
            .inc();
        self.inner
            .http_request_duration
            .get_or_create(&HttpRouteLabels {
                method: method.to_owned(),
                route: route.to_owned(),
            })
            .observe(elapsed.as_secs_f64());
    }

    /// Counts one failed Redis hint operation `op` (`publish`, `subscribe`, `rate_limit`, …).
    pub fn record_hints_error(&self, op: &str) {
        self.inner
            .hints_errors
            .get_or_create(&OpLabels { op: op.to_owned() })
            .inc();
    }

    /// Every family in the OpenMetrics text format (serve with content type
    /// [`Metrics::CONTENT_TYPE`]).
    #[must_use]
    pub fn encode(&self) -> String {
        // Not in the middle of a gauge refresh (which clears, then refills, its families).
        let _serial = self
            .inner
            .refresh
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let mut text = String::new();
        // Writing to a String cannot fail; label values are escaped by the encoder.
        if prometheus_client::encoding::text::encode(&mut text, &self.inner.registry).is_err() {
            text.clear();
        }
        text
    }

    /// The content type of [`Metrics::encode`]'s output.
    pub const CONTENT_TYPE: &'static str =
        "application/openmetrics-text; version=1.0.0; charset=utf-8";
}

fn stage_labels(stage: &str) -> StageLabels {
    StageLabels {
        stage: stage.to_owned(),
    }
}
