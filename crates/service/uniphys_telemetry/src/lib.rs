//! Service telemetry for UniPhys: structured logs (text or JSON), Prometheus metrics of the
//! queue, the stages and the HTTP API, and OpenTelemetry traces exported over OTLP/HTTP
//! (protobuf; off unless an endpoint is configured).
//!
//! - [`init`] installs the process's tracing subscriber from a [`TelemetryConfig`] and returns
//!   a [`TelemetryGuard`] that flushes traces when dropped; [`subscriber`], [`fmt_layer`],
//!   [`otel_layer`] and [`tracer_provider`] build the same pieces without installing them.
//! - Traces cross the queue as W3C `traceparent` strings: [`current_traceparent`] at submit,
//!   stored with the job; [`stage_span`] in the worker makes the stage's span a child of it, so
//!   one trace runs from the HTTP request through every stage. [`http_request_span`] and
//!   [`context_from_headers`] join a caller's trace from request headers.
//! - [`Metrics`] holds every Prometheus family; [`Metrics::encode`] renders `/metrics`, and
//!   [`Metrics::refresh_queue_gauges`] reads queue depth and table health from the store.

mod config;
mod error;
mod http_client;
mod metrics;
mod propagation;
mod subscriber;

pub use config::{LogFormat, TelemetryConfig};
pub use error::{TelemetryError, TelemetryResult};
pub use metrics::{Metrics, StageOutcome};
pub use propagation::{
    context_from_headers, context_from_traceparent, current_traceparent, http_request_span,
    inject_current_context, stage_span, traceparent_of,
};
pub use subscriber::{TelemetryGuard, fmt_layer, init, otel_layer, subscriber, tracer_provider};
