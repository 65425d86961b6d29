//! One trace from the HTTP request through every stage: `uniphys serve` with an OTLP endpoint
//! (a local stand-in collector that records what it receives), one upload, and the trace id stored
//! with the job must appear on the exported request span and on the stage's span.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Accepts OTLP/HTTP posts and keeps their bodies.
fn collector() -> (u16, Arc<Mutex<Vec<Vec<u8>>>>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("collector port");
    let port = listener.local_addr().expect("address").port();
    let bodies = Arc::new(Mutex::new(Vec::new()));
    let sink = Arc::clone(&bodies);
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let mut reader = BufReader::new(stream);
            let mut length = 0usize;
            loop {
                let mut line = String::new();
                if reader.read_line(&mut line).unwrap_or(0) == 0 {
                    break;
                }
                let lower = line.to_ascii_lowercase();
                if let Some(value) = lower.strip_prefix("content-length:") {
                    length = value.trim().parse().unwrap_or(0);
                }
                if line == "\r\n" {
                    let mut body = vec![0; length];
                    if reader.read_exact(&mut body).is_ok() {
                        sink.lock().expect("lock").push(body);
                    }
                    let _ = reader
                        .get_mut()
                        .write_all(b"HTTP/1.1 200 OK\r\ncontent-length: 0\r\n\r\n");
                    length = 0;
                }
            }
        }
    });
    (port, bodies)
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

/// Whether a span called `name` in an OTLP protobuf body belongs to `trace_id`: a span encodes
/// its trace id (field 1), span id (2) and parent span id (4) just before its name (5), so the
/// trace id field sits in the 64 bytes before the name.
fn span_in_trace(body: &[u8], name: &[u8], trace_id: &[u8]) -> bool {
    let mut field = vec![0x0a, 0x10];
    field.extend_from_slice(trace_id);
    body.windows(name.len())
        .enumerate()
        .filter(|(_, w)| *w == name)
        .any(|(at, _)| contains(&body[at.saturating_sub(64)..at], &field))
}

#[test]
fn the_request_and_its_stages_share_one_trace() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (collector_port, bodies) = collector();
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("free port");
    let api_url = format!("http://127.0.0.1:{port}");
    let base = |command: &mut Command| {
        command
            .env_clear()
            .env("PATH", std::env::var("PATH").unwrap_or_default())
            .env("UNIPHYS_DATA_DIR", dir.path())
            .env("UNIPHYS_API_URL", &api_url);
    };
    let mut serve = Command::new(env!("CARGO_BIN_EXE_uniphys"));
    base(&mut serve);
    let mut server = serve
        .args(["serve", "--listen", &format!("127.0.0.1:{port}")])
        .args(["--stand-ins", "first,second", "--stand-in-work-ms", "5"])
        .env(
            "UNIPHYS_OTLP_ENDPOINT",
            format!("http://127.0.0.1:{collector_port}"),
        )
        .env("UNIPHYS_LOG", "warn")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("serve starts");
    let mut lines = BufReader::new(server.stderr.take().expect("stderr")).lines();
    let until = Instant::now() + Duration::from_secs(60);
    while !lines
        .next()
        .expect("serve runs")
        .expect("line")
        .starts_with("API on")
    {
        assert!(Instant::now() < until, "serve did not start");
    }
    std::thread::spawn(move || lines.for_each(drop));

    let file = dir.path().join("anything.stl");
    std::fs::write(&file, b"solid x\nendsolid x\n").expect("write");
    let mut submit = Command::new(env!("CARGO_BIN_EXE_uniphys"));
    base(&mut submit);
    let out = submit
        .arg("submit")
        .arg("--watch")
        .arg(&file)
        .output()
        .expect("submit");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let kill = Command::new("kill")
        .args(["-TERM", &server.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    assert!(server.wait().expect("exit").success());

    let db = std::fs::read(dir.path().join("queue.db")).expect("queue database");
    // The job's stored traceparent: 00-<32 hex trace id>-<16 hex span id>-01.
    let marker = b"\"trace_parent\":\"00-";
    let at = db
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("the job stored the request's traceparent");
    let hex_id = std::str::from_utf8(&db[at + marker.len()..at + marker.len() + 32]).expect("hex");
    let trace_id: Vec<u8> = (0..16)
        .map(|i| u8::from_str_radix(&hex_id[2 * i..2 * i + 2], 16).expect("hex digit"))
        .collect();
    let bodies = bodies.lock().expect("lock");
    assert!(!bodies.is_empty(), "no traces reached the collector");
    let all: Vec<u8> = bodies.concat();
    for span in [&b"POST /v1/assets"[..], b"stage first", b"stage second"] {
        assert!(
            contains(&all, span),
            "{} was not exported",
            String::from_utf8_lossy(span)
        );
    }
    for span in [&b"POST /v1/assets"[..], b"stage first", b"stage second"] {
        assert!(
            bodies.iter().any(|b| span_in_trace(b, span, &trace_id)),
            "{} is not in the request's trace {hex_id}",
            String::from_utf8_lossy(span)
        );
    }
}
