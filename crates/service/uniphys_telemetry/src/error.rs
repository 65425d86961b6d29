//! The one error type of this crate.

/// What can go wrong setting up or feeding telemetry.
#[derive(Debug, thiserror::Error)]
pub enum TelemetryError {
    /// The log filter is not valid `EnvFilter` syntax.
    #[error("invalid log filter {filter:?}: {message}")]
    LogFilter {
        /// The filter as given.
        filter: String,
        /// Why it was rejected.
        message: String,
    },
    /// The OTLP endpoint is not a plain `http://` URL.
    #[error("invalid OTLP endpoint {endpoint:?}: {message}")]
    OtlpEndpoint {
        /// The endpoint as given.
        endpoint: String,
        /// Why it was rejected.
        message: String,
    },
    /// The OTLP span exporter could not be built.
    #[error("cannot build the OTLP span exporter: {0}")]
    Exporter(#[from] opentelemetry_otlp::ExporterBuildError),
    /// Another global tracing subscriber is installed already.
    #[error("a global tracing subscriber is already installed")]
    SubscriberAlreadySet,
    /// Flushing or shutting down the tracer provider failed (spans may be lost).
    #[error("flushing traces failed: {0}")]
    Flush(#[from] opentelemetry_sdk::error::OTelSdkError),
    /// Reading queue statistics for the gauges failed.
    #[error("reading queue statistics: {0}")]
    Queue(#[from] uniphys_queue::QueueError),
}

/// Result of this crate's fallible functions.
pub type TelemetryResult<T> = Result<T, TelemetryError>;
