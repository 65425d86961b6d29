//! Over a real socket, through the API's own accept loop: a chunked upload larger than axum's
//! default body limit streams through and an artifact streams back with its length; a client
//! that sends its headers too slowly is cut off, one that stalls its upload gets 408, and one
//! address cannot hold more connections than its cap.

use std::io::Read;
use std::time::Duration;

use sha2::{Digest, Sha256};
use uniphys_queue::{ArtifactEntry, Backend, OutputManifest, StageCost, WorkerId};

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use uniphys_api::{ConnectionLimits, serve_with_limits};

use crate::harness::{KEY, TestApp};

/// Bytes `0, 1, …, 250, 0, 1, …` produced `total` at a time in odd-sized reads.
struct Pattern {
    left: usize,
    next: u8,
}

impl Read for Pattern {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.left).min(70_001);
        for b in &mut buf[..n] {
            *b = self.next;
            self.next = (self.next + 1) % 251;
        }
        self.left -= n;
        Ok(n)
    }
}

fn pattern(total: usize) -> Vec<u8> {
    let mut bytes = Vec::new();
    Pattern {
        left: total,
        next: 0,
    }
    .read_to_end(&mut bytes)
    .expect("read");
    bytes
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_large_chunked_upload_and_a_download_stream_over_http() {
    let Some(app) = TestApp::open(Backend::Sqlite, |c| c.with_max_upload_bytes(8 << 20)).await
    else {
        return;
    };
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let base = format!("http://{}", listener.local_addr().expect("addr"));
    let router = app.router.clone();
    let server = tokio::spawn(serve_with_limits(
        listener,
        router,
        ConnectionLimits::default(),
        std::future::pending(),
    ));

    let total = 5 << 20;
    let url = format!("{base}/v1/assets?filename=big.glb");
    let (status, body) = tokio::task::spawn_blocking(move || {
        let client = reqwest::blocking::Client::builder()
            .timeout(Duration::from_secs(60))
            .build()
            .expect("client");
        // A body of unknown length: sent chunked.
        let response = client
            .post(&url)
            .header("authorization", format!("Bearer {KEY}"))
            .body(reqwest::blocking::Body::new(Pattern {
                left: total,
                next: 0,
            }))
            .send()
            .expect("upload");
        let status = response.status().as_u16();
        (status, response.text().expect("body"))
    })
    .await
    .expect("client task");
    assert_eq!(status, 201, "{body}");
    let json: serde_json::Value = serde_json::from_str(&body).expect("json");
    let expected = pattern(total);
    assert_eq!(json["size_bytes"], total);
    assert_eq!(
        json["content_digest"],
        format!("sha256:{}", hex::encode(Sha256::digest(&expected)))
    );
    let asset = json["asset_id"].as_str().expect("asset").to_owned();

    // Complete the first stage with a 3 MiB artifact and download it over the socket.
    let run = &app
        .store
        .claim(
            &WorkerId("w".into()),
            &["ingest"],
            Duration::from_secs(600),
            1,
        )
        .await
        .expect("claim")[0];
    let artifact = pattern(3 << 20);
    let key = format!("{}/ingest/v1/x/mesh.obj", run.asset_id.0);
    app.artifacts
        .put(&key, artifact.clone())
        .await
        .expect("put");
    let manifest = OutputManifest {
        artifacts: vec![ArtifactEntry {
            name: "mesh.obj".into(),
            key,
            bytes: artifact.len() as u64,
            sha256: hex::encode(Sha256::digest(&artifact)),
        }],
        summary: serde_json::Value::Null,
    };
    app.store
        .complete(&run.lease, &manifest.to_value(), &StageCost::default())
        .await
        .expect("complete");
    let url = format!("{base}/v1/assets/{asset}/artifacts/ingest/mesh.obj");
    let (status, length, downloaded) = tokio::task::spawn_blocking(move || {
        let mut response = reqwest::blocking::Client::new()
            .get(&url)
            .header("authorization", format!("Bearer {KEY}"))
            .send()
            .expect("download");
        let length = response
            .headers()
            .get("content-length")
            .and_then(|v| v.to_str().ok())
            .map(str::to_owned);
        let mut bytes = Vec::new();
        response.read_to_end(&mut bytes).expect("read");
        (response.status().as_u16(), length, bytes)
    })
    .await
    .expect("client task");
    assert_eq!(status, 200);
    assert_eq!(length.as_deref(), Some("3145728"));
    assert!(downloaded == artifact, "downloaded bytes differ");
    server.abort();
    app.finish().await;
}

/// Serves `app` on a loopback port within `limits`; returns its address.
async fn serve_app(app: &TestApp, limits: ConnectionLimits) -> std::net::SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let address = listener.local_addr().expect("addr");
    tokio::spawn(serve_with_limits(
        listener,
        app.router.clone(),
        limits,
        std::future::pending(),
    ));
    address
}

/// Reads until the server closes the connection or `within` passes; what arrived, and whether
/// it closed.
async fn read_until_closed(stream: &mut TcpStream, within: Duration) -> (String, bool) {
    let mut received = Vec::new();
    let mut buf = [0u8; 4096];
    let closed = tokio::time::timeout(within, async {
        loop {
            match stream.read(&mut buf).await {
                Ok(0) | Err(_) => return,
                Ok(n) => received.extend_from_slice(&buf[..n]),
            }
        }
    })
    .await
    .is_ok();
    (String::from_utf8_lossy(&received).into_owned(), closed)
}

/// A complete `GET /healthz` on a new connection answers 200.
async fn healthy(address: std::net::SocketAddr) -> bool {
    let mut stream = TcpStream::connect(address).await.expect("connect");
    stream
        .write_all(b"GET /healthz HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n")
        .await
        .expect("write");
    let (answer, _) = read_until_closed(&mut stream, Duration::from_secs(10)).await;
    answer.starts_with("HTTP/1.1 200")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_sending_its_headers_too_slowly_is_cut_off() {
    let Some(app) = TestApp::open(Backend::Sqlite, |c| c).await else {
        return;
    };
    let limits = ConnectionLimits {
        header_read_timeout: Duration::from_millis(500),
        ..ConnectionLimits::default()
    };
    let address = serve_app(&app, limits).await;
    let mut slow = TcpStream::connect(address).await.expect("connect");
    slow.write_all(b"GET /healthz HTTP/1.1\r\nHost: t\r\n")
        .await
        .expect("write");
    // One more header line now and then, never the blank line that ends them.
    let trickle = async {
        for _ in 0..20 {
            tokio::time::sleep(Duration::from_millis(200)).await;
            if slow.write_all(b"X-Slow: 1\r\n").await.is_err() {
                return;
            }
        }
    };
    let _ = tokio::time::timeout(Duration::from_secs(5), trickle).await;
    let (_, closed) = read_until_closed(&mut slow, Duration::from_secs(5)).await;
    assert!(closed, "the slow client still holds its connection");
    assert!(healthy(address).await, "the server answers others");
    app.finish().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_upload_that_stalls_after_its_headers_gets_408_and_nothing_is_stored() {
    let Some(app) = TestApp::open(Backend::Sqlite, |c| {
        c.with_body_read_timeout(Duration::from_millis(500))
    })
    .await
    else {
        return;
    };
    let address = serve_app(&app, ConnectionLimits::default()).await;
    let mut stream = TcpStream::connect(address).await.expect("connect");
    let head = format!(
        "POST /v1/assets?filename=stall.glb HTTP/1.1\r\nHost: t\r\nAuthorization: Bearer {KEY}\r\n\
         Content-Type: application/octet-stream\r\nContent-Length: 1000\r\n\r\n"
    );
    stream.write_all(head.as_bytes()).await.expect("write");
    stream.write_all(&[7u8; 100]).await.expect("write");
    let (answer, _) = read_until_closed(&mut stream, Duration::from_secs(10)).await;
    assert!(answer.starts_with("HTTP/1.1 408"), "{answer}");
    assert!(answer.contains("request_timeout"), "{answer}");
    app.assert_nothing_submitted().await;
    app.finish().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_address_holds_at_most_its_cap_of_connections() {
    let Some(app) = TestApp::open(Backend::Sqlite, |c| c).await else {
        return;
    };
    let limits = ConnectionLimits {
        max_connections_per_address: 2,
        ..ConnectionLimits::default()
    };
    let address = serve_app(&app, limits).await;
    let first = TcpStream::connect(address).await.expect("connect");
    let _second = TcpStream::connect(address).await.expect("connect");
    // Accepted by the kernel, then closed by the server without an answer.
    let mut third = TcpStream::connect(address).await.expect("connect");
    let (answer, closed) = read_until_closed(&mut third, Duration::from_secs(5)).await;
    assert!(
        closed && answer.is_empty(),
        "a third connection was served: {answer:?}"
    );
    drop(first);
    // The server sees the close and frees the place.
    let mut served = false;
    for _ in 0..50 {
        if healthy(address).await {
            served = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(
        served,
        "a place freed by a closed connection is not given back"
    );
    app.finish().await;
}
