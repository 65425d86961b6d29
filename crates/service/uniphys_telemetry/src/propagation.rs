//! W3C trace context across process boundaries: from HTTP headers into the request's span,
//! from the submitting span into the job (a `traceparent` string), and from the job into each
//! stage's span in the worker, so one trace covers a job from request to last stage.
//!
//! All of it is inert when trace export is off: spans have no OpenTelemetry context, so
//! [`current_traceparent`] returns `None` and parents are not set.

use std::collections::HashMap;

use opentelemetry::Context;
use opentelemetry::propagation::TextMapPropagator as _;
use opentelemetry::trace::TraceContextExt as _;
use opentelemetry_http::{HeaderExtractor, HeaderInjector};
use opentelemetry_sdk::propagation::TraceContextPropagator;
use tracing::Span;
use tracing_opentelemetry::OpenTelemetrySpanExt as _;

/// The W3C header (and carrier key) naming the parent span.
const TRACEPARENT: &str = "traceparent";

/// The `traceparent` of the current span (`00-<trace id>-<span id>-<flags>`), to store with a
/// job at submit; `None` when the span has no trace (export off, or no span).
#[must_use]
pub fn current_traceparent() -> Option<String> {
    traceparent_of(&Span::current())
}

/// The `traceparent` of `span`; `None` when it has no trace.
#[must_use]
pub fn traceparent_of(span: &Span) -> Option<String> {
    let cx = span.context();
    if !cx.span().span_context().is_valid() {
        return None;
    }
    let mut carrier = HashMap::new();
    TraceContextPropagator::new().inject_context(&cx, &mut carrier);
    carrier.remove(TRACEPARENT)
}

/// The remote parent named by a `traceparent` string; `None` when it is malformed.
#[must_use]
pub fn context_from_traceparent(traceparent: &str) -> Option<Context> {
    let carrier = HashMap::from([(TRACEPARENT.to_owned(), traceparent.trim().to_owned())]);
    let cx = TraceContextPropagator::new().extract(&carrier);
    cx.span().span_context().is_valid().then_some(cx)
}

/// The remote parent named by an incoming request's `traceparent` (and `tracestate`) headers;
/// an empty context when there is none.
#[must_use]
pub fn context_from_headers(headers: &http::HeaderMap) -> Context {
    TraceContextPropagator::new().extract(&HeaderExtractor(headers))
}

/// Writes the current span's `traceparent` (and `tracestate`) into outgoing request headers.
pub fn inject_current_context(headers: &mut http::HeaderMap) {
    let cx = Span::current().context();
    if cx.span().span_context().is_valid() {
        TraceContextPropagator::new().inject_context(&cx, &mut HeaderInjector(headers));
    }
}

/// The span of one HTTP request, named `<METHOD> <route>` (route as matched, e.g.
/// `/v1/jobs/{id}`, never the raw path), child of the caller's trace when the headers carry
/// one. Its `http.response.status_code` field is empty: record it when the response is known.
#[must_use]
pub fn http_request_span(method: &http::Method, route: &str, headers: &http::HeaderMap) -> Span {
    let span = tracing::info_span!(
        "http_request",
        otel.name = %format_args!("{method} {route}"),
        otel.kind = "server",
        http.request.method = %method,
        http.route = route,
        http.response.status_code = tracing::field::Empty,
    );
    let parent = context_from_headers(headers);
    if parent.span().span_context().is_valid() {
        // Fails only when no OpenTelemetry layer is installed or the span is filtered out:
        // then there is no trace to join.
        let _ = span.set_parent(parent);
    }
    span
}

/// The span of one attempt of one stage run in a worker, named `stage <stage>`, whose parent is
/// the trace stored with the job (`traceparent` from [`current_traceparent`] at submit), so the
/// stage joins the trace of the request that submitted the job. A missing or malformed
/// `traceparent` starts a new trace (or none, when export is off).
#[must_use]
pub fn stage_span(
    stage: &str,
    job_id: i64,
    run_id: i64,
    attempt: u32,
    traceparent: Option<&str>,
) -> Span {
    let span = tracing::info_span!(
        "stage",
        otel.name = %format_args!("stage {stage}"),
        otel.kind = "consumer",
        stage,
        job_id,
        run_id,
        attempt,
    );
    if let Some(parent) = traceparent.and_then(context_from_traceparent) {
        // As in `http_request_span`: an error means there is no trace to join.
        let _ = span.set_parent(parent);
    }
    span
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "00-4bf92f3577b34da6a3ce929d0e0e4736-00f067aa0ba902b7-01";

    #[test]
    fn a_valid_traceparent_parses_and_garbage_does_not() {
        let cx = context_from_traceparent(SAMPLE).expect("valid traceparent");
        assert_eq!(
            cx.span().span_context().trace_id().to_string(),
            "4bf92f3577b34da6a3ce929d0e0e4736"
        );
        assert!(context_from_traceparent("00-zz-yy-01").is_none());
        assert!(context_from_traceparent("").is_none());
    }

    #[test]
    fn headers_carry_the_parent() {
        let mut headers = http::HeaderMap::new();
        headers.insert(TRACEPARENT, SAMPLE.parse().expect("header value"));
        let cx = context_from_headers(&headers);
        assert_eq!(
            cx.span().span_context().span_id().to_string(),
            "00f067aa0ba902b7"
        );
        let empty = context_from_headers(&http::HeaderMap::new());
        assert!(!empty.span().span_context().is_valid());
    }

    #[test]
    fn without_an_otel_layer_there_is_no_traceparent() {
        let span = stage_span("ingest", 1, 2, 1, Some(SAMPLE));
        let _entered = span.enter();
        assert_eq!(current_traceparent(), None);
    }
}
