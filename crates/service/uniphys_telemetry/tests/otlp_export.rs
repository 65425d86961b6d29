//! With an OTLP endpoint configured, spans reach a collector as OTLP/HTTP protobuf when the
//! guard shuts down, and a stage span started from a stored `traceparent` joins the trace of
//! the span that stored it.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::{Arc, Mutex};

use uniphys_telemetry::{
    TelemetryConfig, current_traceparent, http_request_span, stage_span, subscriber, traceparent_of,
};

/// One request the fake collector received.
#[derive(Clone, Debug)]
struct Received {
    request_line: String,
    content_type: String,
    body: Vec<u8>,
}

/// A fake collector on a loopback port: answers every request 200 and records it.
fn start_collector() -> (String, Arc<Mutex<Vec<Received>>>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind loopback");
    let addr = listener.local_addr().expect("local addr");
    let received = Arc::new(Mutex::new(Vec::new()));
    let log = Arc::clone(&received);
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let log = Arc::clone(&log);
            std::thread::spawn(move || serve(stream, &log));
        }
    });
    (format!("http://{addr}"), received)
}

fn serve(stream: TcpStream, log: &Mutex<Vec<Received>>) {
    let mut writer = stream.try_clone().expect("clone stream");
    let mut reader = BufReader::new(stream);
    loop {
        let mut request_line = String::new();
        if reader.read_line(&mut request_line).unwrap_or(0) == 0 {
            return;
        }
        let mut content_length = 0;
        let mut content_type = String::new();
        loop {
            let mut line = String::new();
            if reader.read_line(&mut line).unwrap_or(0) == 0 {
                return;
            }
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some((name, value)) = line.split_once(':') {
                match name.trim().to_ascii_lowercase().as_str() {
                    "content-length" => content_length = value.trim().parse().unwrap_or(0),
                    "content-type" => value.trim().clone_into(&mut content_type),
                    _ => {}
                }
            }
        }
        let mut body = vec![0; content_length];
        if reader.read_exact(&mut body).is_err() {
            return;
        }
        log.lock().expect("log lock").push(Received {
            request_line: request_line.trim_end().to_owned(),
            content_type,
            body,
        });
        if writer
            .write_all(b"HTTP/1.1 200 OK\r\ncontent-length: 0\r\n\r\n")
            .is_err()
        {
            return;
        }
    }
}

fn hex_bytes(hex: &str) -> Vec<u8> {
    (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).expect("hex digit pair"))
        .collect()
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

#[test]
fn spans_reach_the_collector_and_stages_join_the_request_trace() {
    let (endpoint, received) = start_collector();
    let config = TelemetryConfig::new("uniphys-telemetry-test")
        .with_otlp_endpoint(&endpoint)
        .with_log_filter("info");
    let (subscriber, guard) = subscriber(&config).expect("subscriber");
    assert!(guard.tracer_provider().is_some(), "export is on");

    let (request_tp, stage_tp) = tracing::subscriber::with_default(subscriber, || {
        let request = http_request_span(&http::Method::POST, "/v1/jobs", &http::HeaderMap::new());
        // At submit: the request's traceparent is stored with the job.
        let stored = request
            .in_scope(current_traceparent)
            .expect("request has a trace");
        drop(request);
        // In the worker, later: the stage span is parented on the stored traceparent.
        let stage = stage_span("ingest", 7, 70, 1, Some(&stored));
        let stage_tp = stage
            .in_scope(current_traceparent)
            .expect("stage has a trace");
        drop(stage);
        (stored, stage_tp)
    });
    // traceparent = 00-<32 hex trace id>-<16 hex span id>-<flags>
    let parts = |tp: &str| tp.split('-').map(str::to_owned).collect::<Vec<_>>();
    let (request_parts, stage_parts) = (parts(&request_tp), parts(&stage_tp));
    assert_eq!(request_parts.len(), 4, "{request_tp}");
    assert_eq!(request_parts[1], stage_parts[1], "same trace id");
    assert_ne!(request_parts[2], stage_parts[2], "different spans");

    guard.shutdown().expect("flush and shut down");

    let received = received.lock().expect("log lock").clone();
    assert!(!received.is_empty(), "the collector received nothing");
    let trace_id = hex_bytes(&request_parts[1]);
    let mut bodies = Vec::new();
    for request in &received {
        assert_eq!(request.request_line, "POST /v1/traces HTTP/1.1");
        assert_eq!(request.content_type, "application/x-protobuf");
        bodies.extend_from_slice(&request.body);
    }
    assert!(contains(&bodies, b"uniphys-telemetry-test"), "service.name");
    assert!(contains(&bodies, b"POST /v1/jobs"), "request span");
    assert!(contains(&bodies, b"stage ingest"), "stage span");
    assert!(contains(&bodies, &trace_id), "the shared trace id");
    assert!(
        contains(&bodies, &hex_bytes(&stage_parts[2])),
        "stage span id"
    );
}

#[test]
fn a_request_span_joins_the_callers_trace_from_its_headers() {
    let (endpoint, _received) = start_collector();
    let config = TelemetryConfig::new("uniphys-telemetry-test").with_otlp_endpoint(&endpoint);
    let (subscriber, guard) = subscriber(&config).expect("subscriber");
    let caller = "00-4bf92f3577b34da6a3ce929d0e0e4736-00f067aa0ba902b7-01";
    let mut headers = http::HeaderMap::new();
    headers.insert("traceparent", caller.parse().expect("header value"));
    let ours = tracing::subscriber::with_default(subscriber, || {
        let span = http_request_span(&http::Method::GET, "/v1/jobs/{id}", &headers);
        traceparent_of(&span).expect("request has a trace")
    });
    assert!(
        ours.starts_with("00-4bf92f3577b34da6a3ce929d0e0e4736-"),
        "{ours}"
    );
    assert!(
        !ours.contains("00f067aa0ba902b7"),
        "a child, not the caller's span"
    );
    drop(guard);
}

#[test]
fn export_is_off_without_an_endpoint() {
    let (subscriber, guard) = subscriber(&TelemetryConfig::new("quiet")).expect("subscriber");
    assert!(guard.tracer_provider().is_none());
    let tp = tracing::subscriber::with_default(subscriber, || {
        let span = stage_span("ingest", 1, 1, 1, None);
        span.in_scope(current_traceparent)
    });
    assert_eq!(tp, None);
}
