//! Over a real socket: a chunked upload larger than axum's default body limit streams through,
//! and an artifact streams back with its length.

use std::io::Read;
use std::time::Duration;

use sha2::{Digest, Sha256};
use uniphys_queue::{ArtifactEntry, Backend, OutputManifest, StageCost, WorkerId};

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
    let server = tokio::spawn(async move { axum::serve(listener, router).await });

    let total = 5 << 20;
    let url = format!("{base}/v1/assets?filename=big.glb");
    let (status, body) = tokio::task::spawn_blocking(move || {
        let agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(60)))
            .build()
            .new_agent();
        let mut response = agent
            .post(&url)
            .header("authorization", &format!("Bearer {KEY}"))
            .send(ureq::SendBody::from_owned_reader(Pattern {
                left: total,
                next: 0,
            }))
            .expect("upload");
        let status = response.status().as_u16();
        (status, response.body_mut().read_to_string().expect("body"))
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
        let mut response = ureq::get(&url)
            .header("authorization", &format!("Bearer {KEY}"))
            .call()
            .expect("download");
        let length = response
            .headers()
            .get("content-length")
            .and_then(|v| v.to_str().ok())
            .map(str::to_owned);
        let mut bytes = Vec::new();
        response
            .body_mut()
            .as_reader()
            .read_to_end(&mut bytes)
            .expect("read");
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
