//! Client overheads: `cargo bench -p uniphys_lvlm --bench client`.
//!
//! 1. Building a request body and its digest (base64 of the images, canonical JSON, SHA-256)
//!    for a properties request of 10 part composites of 200 kB each; median of a few runs.
//! 2. Wall time of 64 requests sent from 64 threads against a local recorded-answer server
//!    answering after a fixed delay, at client concurrency 1, 8 and 32, with the server's peak
//!    of requests in flight (the ideal is `ceil(64 / concurrency) * delay`).
//! 3. Round-trip time of one request to a local server answering at once (client overhead).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a benchmark binary: setup failures panic

use std::sync::Arc;
use std::time::Instant;

use serde_json::json;
use uniphys_lvlm::{ChatRequest, CostLedger, LvlmClient, LvlmConfig, NoCache, NoRateLimit};
use uniphys_replay::{Exchange, Recording, ReplayServer, Reply};

const IMAGES: usize = 10;
const IMAGE_BYTES: usize = 200_000;
const REQUESTS: usize = 64;
const DELAY_MS: u64 = 100;
const RUNS: usize = 5;

/// Median wall-clock milliseconds of `runs` calls of `f`.
fn median_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// A PNG signature followed by pseudo-random bytes (incompressible, like real renders).
fn fake_png(seed: u64) -> Vec<u8> {
    let mut bytes = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    while bytes.len() < IMAGE_BYTES {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        bytes.extend_from_slice(&state.to_le_bytes());
    }
    bytes
}

fn server(delay_ms: u64) -> ReplayServer {
    let answer = json!({
        "model": "bench",
        "choices": [{"finish_reason": "stop", "message": {"content": "===BEGIN_JSON==={}===END_JSON==="}}],
        "usage": {"prompt_tokens": 1000, "completion_tokens": 200},
    });
    ReplayServer::start(Recording {
        exchanges: vec![Exchange {
            method: "POST".to_owned(),
            path: "/v1/chat/completions".to_owned(),
            body_contains: Vec::new(),
            replies: vec![Reply::json(200, answer).with_delay_ms(delay_ms)],
        }],
    })
    .expect("replay server")
}

fn client(server: &ReplayServer, max_concurrency: usize) -> LvlmClient {
    let config = LvlmConfig {
        base_url: format!("{}/v1", server.url()),
        max_concurrency,
        ..LvlmConfig::default()
    };
    LvlmClient::new(config, Arc::new(NoRateLimit), Arc::new(NoCache)).expect("client")
}

fn main() {
    let mut request = ChatRequest::new("properties", "system prompt ".repeat(700), "user text");
    for i in 0..IMAGES {
        request = request.with_image(fake_png(i as u64));
    }
    let config = LvlmConfig::default();
    let build_ms = median_ms(RUNS, || {
        std::hint::black_box(request.body(&config).unwrap());
    });
    let body_bytes = request.body(&config).unwrap().json.len();
    println!("request body: {IMAGES} images x {IMAGE_BYTES} B -> {body_bytes} B JSON");
    println!("| step | median ms |");
    println!("|---|---|");
    println!("| body + digest | {build_ms:.2} |");
    println!();

    println!("{REQUESTS} requests from {REQUESTS} threads, server delay {DELAY_MS} ms");
    println!("| concurrency | wall s | ideal s | requests/s | server peak in flight |");
    println!("|---|---|---|---|---|");
    for concurrency in [1usize, 8, 32] {
        let server = server(DELAY_MS);
        let client = Arc::new(client(&server, concurrency));
        let ledger = Arc::new(CostLedger::unlimited());
        let start = Instant::now();
        let threads: Vec<_> = (0..REQUESTS)
            .map(|i| {
                let (client, ledger) = (Arc::clone(&client), Arc::clone(&ledger));
                std::thread::spawn(move || {
                    let request = ChatRequest::new("bench", "s", format!("request {i}"));
                    client.complete(&request, &ledger).unwrap();
                })
            })
            .collect();
        for thread in threads {
            thread.join().unwrap();
        }
        let wall_s = start.elapsed().as_secs_f64();
        let ideal_s = REQUESTS.div_ceil(concurrency) as f64 * DELAY_MS as f64 / 1e3;
        println!(
            "| {concurrency} | {wall_s:.2} | {ideal_s:.2} | {:.1} | {} |",
            REQUESTS as f64 / wall_s,
            server.max_in_flight()
        );
    }
    println!();

    let server = server(0);
    let client = client(&server, 1);
    let ledger = CostLedger::unlimited();
    let mut i = 0;
    let round_trip_ms = median_ms(51, || {
        i += 1;
        let request = ChatRequest::new("bench", "s", format!("ping {i}"));
        client.complete(&request, &ledger).unwrap();
    });
    println!("| local round trip, no delay | {round_trip_ms:.2} ms (median of 51) |");
}
