//! The replay server over real sockets: replies in order, body matching, faults, keep-alive,
//! chunked and large bodies, concurrency accounting, stop releasing hung sockets.

#![allow(clippy::unwrap_used)] // helpers outside #[test] functions

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::sync::Arc;
use std::time::{Duration, Instant};

use uniphys_replay::{Fault, RecordedRequest, Recording, ReplayServer, Reply};

/// A response read off a raw socket.
#[derive(Debug)]
struct Raw {
    status: u16,
    headers: Vec<(String, String)>,
    body: Vec<u8>,
}

impl Raw {
    fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }
}

fn connect(server: &ReplayServer) -> TcpStream {
    let stream = TcpStream::connect(server.address()).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    stream
}

/// Reads one response; the body is read to its `Content-Length` or as far as the peer sent.
fn read_response(reader: &mut BufReader<TcpStream>) -> std::io::Result<Raw> {
    let mut line = String::new();
    if reader.read_line(&mut line)? == 0 {
        return Err(std::io::ErrorKind::UnexpectedEof.into());
    }
    let status: u16 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    let mut headers = Vec::new();
    loop {
        let mut header = String::new();
        reader.read_line(&mut header)?;
        let header = header.trim_end();
        if header.is_empty() {
            break;
        }
        let (n, v) = header.split_once(':').unwrap();
        headers.push((n.trim().to_owned(), v.trim().to_owned()));
    }
    let length: usize = headers
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case("content-length"))
        .map_or(0, |(_, v)| v.parse().unwrap());
    let mut body = Vec::new();
    reader.by_ref().take(length as u64).read_to_end(&mut body)?;
    Ok(Raw {
        status,
        headers,
        body,
    })
}

fn post(path: &str, body: &str) -> String {
    format!(
        "POST {path} HTTP/1.1\r\nHost: x\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
}

fn recording(json: &str) -> Recording {
    Recording::from_json(json).unwrap()
}

#[test]
fn replies_play_in_order_and_the_last_repeats() {
    let server = ReplayServer::start(recording(
        r#"{"exchanges":[{"method":"POST","path":"/v1/x","replies":[
            {"status":429,"headers":{"Retry-After":"3"},"body":"busy"},
            {"status":500,"json":{"error":"boom"}},
            {"json":{"ok":1}}]}]}"#,
    ))
    .unwrap();
    let stream = connect(&server);
    let mut writer = stream.try_clone().unwrap();
    let mut reader = BufReader::new(stream);
    let mut seen = Vec::new();
    for _ in 0..5 {
        writer.write_all(post("/v1/x", "{}").as_bytes()).unwrap();
        let response = read_response(&mut reader).unwrap();
        seen.push((
            response.status,
            String::from_utf8(response.body.clone()).unwrap(),
        ));
        if response.status == 429 {
            assert_eq!(response.header("retry-after"), Some("3"));
        }
        if response.status == 200 {
            assert_eq!(response.header("content-type"), Some("application/json"));
        }
    }
    let statuses: Vec<u16> = seen.iter().map(|(s, _)| *s).collect();
    assert_eq!(statuses, [429, 500, 200, 200, 200]);
    assert_eq!(seen[0].1, "busy");
    assert_eq!(seen[1].1, r#"{"error":"boom"}"#);
    // One socket carried all five requests.
    assert_eq!(server.connection_count(), 1);
    assert_eq!(server.requests().len(), 5);
}

#[test]
fn body_substrings_choose_the_exchange_and_unmatched_requests_get_501() {
    let server = ReplayServer::start(recording(
        r#"{"exchanges":[
            {"method":"POST","path":"/m","body_contains":["\"a\":1","cat"],"replies":[{"body":"first"}]},
            {"method":"post","path":"/m","replies":[{"body":"second"}]}]}"#,
    ))
    .unwrap();
    let stream = connect(&server);
    let mut writer = stream.try_clone().unwrap();
    let mut reader = BufReader::new(stream);
    let mut ask = |path: &str, body: &str| {
        writer.write_all(post(path, body).as_bytes()).unwrap();
        read_response(&mut reader).unwrap()
    };
    assert_eq!(ask("/m", r#"{"a":1,"b":"cat"}"#).body, b"first");
    assert_eq!(ask("/m", r#"{"a":1,"b":"dog"}"#).body, b"second");
    assert_eq!(ask("/m?x=1", r#"{"a":1,"b":"cat"}"#).body, b"first");
    let unmatched = ask("/nowhere", "{}");
    assert_eq!(unmatched.status, 501);
    let value: serde_json::Value = serde_json::from_slice(&unmatched.body).unwrap();
    assert_eq!(value["method"], "POST");
    assert_eq!(value["path"], "/nowhere");
}

#[test]
fn truncate_sends_full_length_header_then_part_of_the_body_and_closes() {
    let server = ReplayServer::start_with(Arc::new(|_: &RecordedRequest| Reply {
        fault: Some(Fault::Truncate { keep_bytes: 4 }),
        ..Reply::text(200, "0123456789")
    }))
    .unwrap();
    let stream = connect(&server);
    let mut writer = stream.try_clone().unwrap();
    let mut reader = BufReader::new(stream);
    writer.write_all(post("/t", "x").as_bytes()).unwrap();
    let response = read_response(&mut reader).unwrap();
    assert_eq!(response.header("content-length"), Some("10"));
    assert_eq!(response.body, b"0123");
    // The connection is closed after the partial body.
    let mut rest = Vec::new();
    assert_eq!(reader.read_to_end(&mut rest).unwrap_or(0), 0);

    // An HTTP client sees an error, not a short body.
    let answer = reqwest::blocking::get(format!("{}/t", server.url())).unwrap();
    assert!(answer.text().is_err());
}

#[test]
fn close_without_reply_sends_nothing() {
    let server = ReplayServer::start_with(Arc::new(|_: &RecordedRequest| {
        Reply::fault(Fault::CloseWithoutReply)
    }))
    .unwrap();
    let mut stream = connect(&server);
    stream.write_all(post("/c", "x").as_bytes()).unwrap();
    let mut rest = Vec::new();
    let read = stream.read_to_end(&mut rest).unwrap_or(0);
    assert_eq!(read, 0);
    assert_eq!(server.requests().len(), 1);
}

#[test]
fn hang_holds_until_the_client_gives_up_and_stop_releases_hung_sockets() {
    let server =
        ReplayServer::start_with(Arc::new(|_: &RecordedRequest| Reply::fault(Fault::Hang)))
            .unwrap();
    // A client with a short timeout gives up.
    let client = reqwest::blocking::Client::builder()
        .timeout(Duration::from_millis(300))
        .build()
        .unwrap();
    let error = client
        .get(format!("{}/h", server.url()))
        .send()
        .unwrap_err();
    assert!(error.is_timeout(), "{error:?}");

    // Two raw sockets stay hung until the server stops.
    let mut hung: Vec<TcpStream> = (0..2)
        .map(|_| {
            let mut stream = connect(&server);
            stream.write_all(post("/h", "x").as_bytes()).unwrap();
            stream
        })
        .collect();
    let deadline = Instant::now() + Duration::from_secs(10);
    while server.requests().len() < 3 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(server.requests().len(), 3);
    assert!(server.max_in_flight() >= 2);
    server.stop();
    for stream in &mut hung {
        let mut rest = Vec::new();
        // EOF (or a reset) instead of the 10 s read timeout.
        match stream.read_to_end(&mut rest) {
            Ok(read) => assert_eq!(read, 0),
            Err(error) => assert_ne!(error.kind(), std::io::ErrorKind::WouldBlock, "{error}"),
        }
    }
}

#[test]
fn keep_alive_reuses_one_connection() {
    let server = ReplayServer::start(recording(
        r#"{"exchanges":[{"method":"GET","path":"/healthz","replies":[{"json":{"status":"ok"}}]}]}"#,
    ))
    .unwrap();
    let client = reqwest::blocking::Client::new();
    for _ in 0..4 {
        let body = client
            .get(format!("{}/healthz", server.url()))
            .send()
            .unwrap()
            .text()
            .unwrap();
        assert_eq!(body, r#"{"status":"ok"}"#);
    }
    assert_eq!(server.requests().len(), 4);
    assert_eq!(server.connection_count(), 1);
}

#[test]
fn chunked_and_large_bodies_arrive_whole() {
    let server = ReplayServer::start_with(Arc::new(|request: &RecordedRequest| {
        Reply::text(200, request.body.len().to_string())
    }))
    .unwrap();
    let stream = connect(&server);
    let mut writer = stream.try_clone().unwrap();
    let mut reader = BufReader::new(stream);
    writer
        .write_all(
            b"POST /c HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n5\r\nhello\r\n6\r\n world\r\n0\r\n\r\n",
        )
        .unwrap();
    assert_eq!(read_response(&mut reader).unwrap().body, b"11");

    // 24 MB of base64-like text through an HTTP client.
    let large: String = (0..24_000_000u32)
        .map(|i| char::from(b'A' + (i % 26) as u8))
        .collect();
    let answer = reqwest::blocking::Client::new()
        .post(format!("{}/big", server.url()))
        .body(large)
        .send()
        .unwrap()
        .text()
        .unwrap();
    assert_eq!(answer, "24000000");
    let requests = server.requests();
    assert_eq!(requests[0].body, b"hello world");
    assert_eq!(requests[1].body.len(), 24_000_000);
    assert_eq!(requests[1].body[..3], *b"ABC");
}

#[test]
fn max_in_flight_counts_32_concurrent_answers() {
    // The responder holds every request until all 32 have arrived (or 20 s passed), so 32
    // connections are being answered at once.
    let arrived = Arc::new((std::sync::Mutex::new(0usize), std::sync::Condvar::new()));
    let gate = Arc::clone(&arrived);
    let server = ReplayServer::start_with(Arc::new(move |_: &RecordedRequest| {
        let (count, all_in) = &*gate;
        let mut count = count.lock().unwrap();
        *count += 1;
        all_in.notify_all();
        let (count, _) = all_in
            .wait_timeout_while(count, Duration::from_secs(20), |n| *n < 32)
            .unwrap();
        Reply::text(200, count.to_string())
    }))
    .unwrap();
    let url = server.url();
    let clients: Vec<_> = (0..32)
        .map(|_| {
            let url = url.clone();
            std::thread::spawn(move || {
                reqwest::blocking::get(format!("{url}/d"))
                    .unwrap()
                    .text()
                    .unwrap()
            })
        })
        .collect();
    for client in clients {
        assert_eq!(client.join().unwrap(), "32");
    }
    assert_eq!(server.requests().len(), 32);
    assert_eq!(server.connection_count(), 32);
    assert_eq!(server.max_in_flight(), 32);
}

#[test]
fn delays_hold_the_answer_and_stop_cuts_them_short() {
    let server = ReplayServer::start_with(Arc::new(|_: &RecordedRequest| {
        Reply::text(200, "late").with_delay_ms(60_000)
    }))
    .unwrap();
    let mut stream = connect(&server);
    stream.write_all(post("/d", "x").as_bytes()).unwrap();
    let deadline = Instant::now() + Duration::from_secs(10);
    while server.requests().is_empty() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(server.max_in_flight(), 1);
    // Stopping does not wait out the minute: the connection closes without an answer.
    server.stop();
    let mut rest = Vec::new();
    let read = stream.read_to_end(&mut rest).unwrap_or(0);
    assert_eq!(read, 0);
}

#[test]
fn bad_recordings_are_refused_with_the_reason() {
    let no_replies =
        Recording::from_json(r#"{"exchanges":[{"method":"GET","path":"/a","replies":[]}]}"#)
            .unwrap_err();
    assert!(
        no_replies.to_string().contains("no replies"),
        "{no_replies}"
    );
    let bad_fault = Recording::from_json(
        r#"{"exchanges":[{"method":"GET","path":"/a","replies":[{"fault":{"kind":"explode"}}]}]}"#,
    );
    assert!(bad_fault.is_err());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("r.json");
    std::fs::write(
        &path,
        r#"{"exchanges":[{"method":"GET","path":"/a","replies":[{"fault":{"kind":"truncate","keep_bytes":3}}]}]}"#,
    )
    .unwrap();
    let loaded = Recording::load(&path).unwrap();
    assert_eq!(
        loaded.exchanges[0].replies[0].fault,
        Some(Fault::Truncate { keep_bytes: 3 })
    );
    assert!(Recording::load(dir.path().join("missing.json")).is_err());
}

#[test]
fn binary_prints_its_url_and_serves_the_recording() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("r.json");
    std::fs::write(
        &path,
        r#"{"exchanges":[{"method":"GET","path":"/healthz","replies":[{"json":{"status":"ok"}}]}]}"#,
    )
    .unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_uniphys-replay"))
        .arg("--recording")
        .arg(&path)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut url = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut url)
        .unwrap();
    let url = url.trim().to_owned();
    let result = reqwest::blocking::get(format!("{url}/healthz")).map(|r| r.text());
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    assert_eq!(result.unwrap().unwrap(), r#"{"status":"ok"}"#);
}
