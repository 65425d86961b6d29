//! The process's tracing subscriber: an `EnvFilter`, a text or JSON log layer on standard error
//! and, when an OTLP endpoint is configured, an OpenTelemetry layer exporting spans in batches.

use std::time::Duration;

use opentelemetry::trace::TracerProvider as _;
use opentelemetry_otlp::{Protocol, WithExportConfig as _, WithHttpConfig as _};
use opentelemetry_sdk::Resource;
use opentelemetry_sdk::propagation::TraceContextPropagator;
use opentelemetry_sdk::trace::{SdkTracer, SdkTracerProvider};
use tracing::Subscriber;
use tracing_opentelemetry::OpenTelemetryLayer;
use tracing_subscriber::fmt::MakeWriter;
use tracing_subscriber::layer::SubscriberExt as _;
use tracing_subscriber::registry::LookupSpan;
use tracing_subscriber::{EnvFilter, Layer, Registry};

use crate::http_client::BlockingClient;
use crate::{LogFormat, TelemetryConfig, TelemetryError, TelemetryResult};

/// How long one export request to the collector may take.
const EXPORT_TIMEOUT: Duration = Duration::from_secs(10);

/// The instrumentation scope spans are recorded under.
const TRACER_NAME: &str = "uniphys";

/// A boxed layer over `S`, as the log formats differ in type.
type BoxedLayer<S> = Box<dyn Layer<S> + Send + Sync + 'static>;

/// Keeps trace export alive; flushes pending spans and stops the exporter when dropped (or
/// when [`TelemetryGuard::shutdown`] is called, which reports failures). Hold it in `main`.
#[derive(Debug)]
#[must_use = "dropping the guard stops trace export"]
pub struct TelemetryGuard {
    provider: Option<SdkTracerProvider>,
}

impl TelemetryGuard {
    /// The tracer provider, when trace export is on.
    #[must_use]
    pub fn tracer_provider(&self) -> Option<&SdkTracerProvider> {
        self.provider.as_ref()
    }

    /// Exports the spans finished so far without stopping export.
    pub fn flush(&self) -> TelemetryResult<()> {
        match &self.provider {
            Some(provider) => Ok(provider.force_flush()?),
            None => Ok(()),
        }
    }

    /// Exports pending spans and stops the exporter.
    pub fn shutdown(mut self) -> TelemetryResult<()> {
        match self.provider.take() {
            Some(provider) => Ok(provider.shutdown()?),
            None => Ok(()),
        }
    }
}

impl Drop for TelemetryGuard {
    fn drop(&mut self) {
        if let Some(provider) = self.provider.take()
            && let Err(e) = provider.shutdown()
        {
            tracing::warn!(error = %e, "flushing traces at exit failed");
        }
    }
}

/// Builds the subscriber described by `config` and installs it for the whole process, with
/// the W3C trace-context propagator and (when export is on) the global tracer provider.
/// Call once, early in `main`; fails if a global subscriber exists already.
pub fn init(config: &TelemetryConfig) -> TelemetryResult<TelemetryGuard> {
    let (subscriber, guard) = subscriber(config)?;
    tracing::subscriber::set_global_default(subscriber)
        .map_err(|_| TelemetryError::SubscriberAlreadySet)?;
    opentelemetry::global::set_text_map_propagator(TraceContextPropagator::new());
    if let Some(provider) = guard.tracer_provider() {
        opentelemetry::global::set_tracer_provider(provider.clone());
    }
    Ok(guard)
}

/// What the trace export records, whatever the log filter: the request and stage spans are `info`.
const TRACE_FILTER: &str = "info";

/// Builds the subscriber described by `config` without installing it (for
/// `tracing::subscriber::with_default` in tests, or to add layers before installing).
pub fn subscriber(
    config: &TelemetryConfig,
) -> TelemetryResult<(Box<dyn Subscriber + Send + Sync>, TelemetryGuard)> {
    let filter = EnvFilter::try_new(&config.log_filter).map_err(|e| TelemetryError::LogFilter {
        filter: config.log_filter.clone(),
        message: e.to_string(),
    })?;
    let provider = tracer_provider(config)?;
    // Each layer filters for itself: quieter logs must not cut the request and stage spans
    // out of the traces.
    let mut layers = vec![fmt_layer(config.log_format).with_filter(filter).boxed()];
    if let Some(provider) = &provider {
        layers.push(
            otel_layer(provider)
                .with_filter(EnvFilter::new(TRACE_FILTER))
                .boxed(),
        );
    }
    let subscriber = Registry::default().with(layers);
    Ok((Box::new(subscriber), TelemetryGuard { provider }))
}

/// The log layer: lines on standard error, as text (coloured on a terminal) or as one JSON
/// object per line (with the current span and the spans it is in).
#[must_use]
pub fn fmt_layer<S>(format: LogFormat) -> BoxedLayer<S>
where
    S: Subscriber + for<'a> LookupSpan<'a>,
{
    let ansi = std::io::IsTerminal::is_terminal(&std::io::stderr());
    fmt_layer_to(format, ansi, std::io::stderr)
}

/// [`fmt_layer`] writing to `writer` (tests capture the lines).
fn fmt_layer_to<S, W>(format: LogFormat, ansi: bool, writer: W) -> BoxedLayer<S>
where
    S: Subscriber + for<'a> LookupSpan<'a>,
    W: for<'w> MakeWriter<'w> + Send + Sync + 'static,
{
    let layer = tracing_subscriber::fmt::layer()
        .with_writer(writer)
        .with_ansi(ansi);
    match format {
        LogFormat::Text => layer.boxed(),
        LogFormat::Json => layer
            .json()
            .with_current_span(true)
            .with_span_list(true)
            .boxed(),
    }
}

/// The layer turning tracing spans into OpenTelemetry spans of `provider`.
#[must_use]
pub fn otel_layer<S>(provider: &SdkTracerProvider) -> OpenTelemetryLayer<S, SdkTracer>
where
    S: Subscriber + for<'a> LookupSpan<'a>,
{
    tracing_opentelemetry::layer().with_tracer(provider.tracer(TRACER_NAME))
}

/// A tracer provider exporting batches of spans in OTLP/HTTP protobuf to the configured
/// endpoint, under `service.name` = `config.service_name`; `None` when no endpoint is set.
pub fn tracer_provider(config: &TelemetryConfig) -> TelemetryResult<Option<SdkTracerProvider>> {
    let Some(url) = config.traces_url()? else {
        return Ok(None);
    };
    let exporter = opentelemetry_otlp::SpanExporter::builder()
        .with_http()
        .with_protocol(Protocol::HttpBinary)
        .with_endpoint(url)
        .with_timeout(EXPORT_TIMEOUT)
        .with_http_client(BlockingClient::new(EXPORT_TIMEOUT))
        .build()?;
    let resource = Resource::builder()
        .with_service_name(config.service_name.clone())
        .build();
    Ok(Some(
        SdkTracerProvider::builder()
            .with_resource(resource)
            .with_batch_exporter(exporter)
            .build(),
    ))
}

#[cfg(test)]
mod tests {
    use std::io::Write;
    use std::sync::{Arc, Mutex};

    use super::*;

    /// Collects written bytes.
    #[derive(Clone, Default)]
    struct Capture(Arc<Mutex<Vec<u8>>>);

    impl Write for Capture {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.lock().expect("capture lock").extend_from_slice(buf);
            Ok(buf.len())
        }

        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl<'w> MakeWriter<'w> for Capture {
        type Writer = Self;

        fn make_writer(&'w self) -> Self::Writer {
            self.clone()
        }
    }

    fn log_one_event(format: LogFormat) -> String {
        let capture = Capture::default();
        let subscriber = Registry::default().with(fmt_layer_to(format, false, capture.clone()));
        tracing::subscriber::with_default(subscriber, || {
            let span = crate::stage_span("decompose", 12, 34, 2, None);
            let _entered = span.enter();
            tracing::info!(parts = 5, "split into parts");
        });
        let bytes = capture.0.lock().expect("capture lock").clone();
        String::from_utf8(bytes).expect("utf-8 log")
    }

    #[test]
    fn json_lines_carry_the_event_and_its_stage_span() {
        let out = log_one_event(LogFormat::Json);
        let line: serde_json::Value =
            serde_json::from_str(out.trim_end()).expect("one JSON object per line");
        assert_eq!(line["level"], "INFO");
        assert_eq!(line["fields"]["message"], "split into parts");
        assert_eq!(line["fields"]["parts"], 5);
        assert_eq!(line["span"]["name"], "stage");
        assert_eq!(line["span"]["stage"], "decompose");
        assert_eq!(line["span"]["job_id"], 12);
        assert_eq!(line["span"]["run_id"], 34);
        assert_eq!(line["span"]["attempt"], 2);
    }

    #[test]
    fn text_lines_name_the_span_fields() {
        let out = log_one_event(LogFormat::Text);
        assert!(out.contains("split into parts"), "{out}");
        assert!(out.contains("stage=\"decompose\""), "{out}");
        assert!(out.contains("job_id=12"), "{out}");
    }
}
