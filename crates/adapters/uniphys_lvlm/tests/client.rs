//! The client against the recorded-answer server: success and cost accounting, every fault
//! path (429, 5xx, timeouts, truncated and malformed bodies, refused requests), the caches,
//! the budget and the concurrency limit.

#![allow(clippy::unwrap_used)] // helpers outside #[test] functions panic on setup failures

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use serde_json::{Value, json};
use uniphys_lvlm::{
    AnswerCache, ChatRequest, CostLedger, DirCache, LvlmClient, LvlmConfig, LvlmError, MemoryCache,
    NoCache, NoRateLimit, Pricing, RateLimiter, extract_marked_json,
};
use uniphys_replay::{Exchange, Fault, RecordedRequest, Recording, ReplayServer, Reply};

const PATH: &str = "/v1/chat/completions";
const KEY: &str = "sk-test-not-a-real-key-4711";

/// A chat-completions answer with `text` and the given usage.
fn completion(text: &str, prompt_tokens: u64, completion_tokens: u64) -> Value {
    json!({
        "id": "chatcmpl-1",
        "object": "chat.completion",
        "model": "replayed-model",
        "choices": [{
            "index": 0,
            "finish_reason": "stop",
            "message": {"role": "assistant", "content": text},
        }],
        "usage": {
            "prompt_tokens": prompt_tokens,
            "completion_tokens": completion_tokens,
            "completion_tokens_details": {"reasoning_tokens": completion_tokens / 2},
        },
    })
}

fn ok(text: &str) -> Reply {
    Reply::json(200, completion(text, 1000, 200))
}

/// A server playing `replies` in order to every chat-completions request.
fn server(replies: Vec<Reply>) -> ReplayServer {
    ReplayServer::start(Recording {
        exchanges: vec![Exchange {
            method: "POST".to_owned(),
            path: PATH.to_owned(),
            body_contains: Vec::new(),
            replies,
        }],
    })
    .unwrap()
}

/// Fast settings for tests: millisecond backoffs, short timeouts, known prices.
fn config(server: &ReplayServer) -> LvlmConfig {
    LvlmConfig {
        base_url: format!("{}/v1", server.url()),
        model: "test-model".to_owned(),
        api_key: Some(KEY.to_owned()),
        reasoning_effort: Some("medium".to_owned()),
        max_completion_tokens: Some(1000),
        connect_timeout_secs: 2.0,
        request_timeout_secs: 5.0,
        max_attempts: 3,
        backoff_initial_secs: 0.001,
        backoff_max_secs: 0.01,
        max_concurrency: 4,
        pricing: Pricing {
            input_usd_per_million_tokens: 1.25,
            output_usd_per_million_tokens: 10.0,
        },
    }
}

fn client(config: LvlmConfig) -> LvlmClient {
    LvlmClient::new(config, Arc::new(NoRateLimit), Arc::new(NoCache)).unwrap()
}

fn client_with_cache(config: LvlmConfig, cache: Arc<dyn AnswerCache>) -> LvlmClient {
    LvlmClient::new(config, Arc::new(NoRateLimit), cache).unwrap()
}

/// A tiny valid PNG header (the client only checks the signature and reads the size).
fn png() -> Vec<u8> {
    let mut bytes = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13];
    bytes.extend_from_slice(b"IHDR");
    bytes.extend_from_slice(&64u32.to_be_bytes());
    bytes.extend_from_slice(&32u32.to_be_bytes());
    bytes
}

fn request(user_text: &str) -> ChatRequest {
    ChatRequest::new("properties", "You annotate parts.", user_text).with_image(png())
}

const EXACT_USD: f64 = 1000.0 * 1.25 / 1e6 + 200.0 * 10.0 / 1e6;

#[test]
fn success_is_charged_at_the_configured_prices() {
    let server = server(vec![ok(
        "===BEGIN_JSON===\n{\"object_name\": \"mug\"}\n===END_JSON===",
    )]);
    let client = client(config(&server));
    let ledger = CostLedger::unlimited();
    let answer = client.complete(&request("two parts"), &ledger).unwrap();

    assert!(!answer.cached);
    assert_eq!(answer.attempts, 1);
    assert_eq!(answer.model, "replayed-model");
    assert_eq!(answer.finish_reason.as_deref(), Some("stop"));
    assert_eq!(
        extract_marked_json(&answer.text).unwrap(),
        json!({"object_name": "mug"})
    );
    assert_eq!(
        (answer.usage.prompt_tokens, answer.usage.completion_tokens),
        (1000, 200)
    );
    assert!(
        (answer.cost_usd - 0.003_25).abs() < 1e-15,
        "{}",
        answer.cost_usd
    );
    assert!((answer.cost_usd - EXACT_USD).abs() < 1e-15);

    let summary = ledger.summary();
    let properties = &summary.by_purpose["properties"];
    assert_eq!(properties.calls, 1);
    assert_eq!(properties.prompt_tokens, 1000);
    assert_eq!(properties.completion_tokens, 200);
    assert_eq!(properties.reasoning_tokens, 100);
    assert!((summary.total.cost_usd - 0.003_25).abs() < 1e-15);

    let requests = server.requests();
    assert_eq!(requests.len(), 1);
    assert_eq!(requests[0].path, PATH);
    assert_eq!(
        requests[0].headers.get("authorization").map(String::as_str),
        Some(format!("Bearer {KEY}").as_str())
    );
    let body: Value = serde_json::from_slice(&requests[0].body).unwrap();
    assert_eq!(body["model"], "test-model");
    assert_eq!(body["reasoning_effort"], "medium");
    assert_eq!(body["max_completion_tokens"], 1000);
    assert_eq!(body["messages"][1]["content"][0]["text"], "two parts");
    assert!(
        body["messages"][1]["content"][1]["image_url"]["url"]
            .as_str()
            .unwrap()
            .starts_with("data:image/png;base64,")
    );
}

#[test]
fn too_many_requests_with_retry_after_then_success() {
    let server = server(vec![
        Reply::json(429, json!({"error": {"message": "rate limited"}}))
            .with_header("Retry-After", "0"),
        ok("fine"),
    ]);
    let client = client(config(&server));
    let ledger = CostLedger::unlimited();
    let answer = client.complete(&request("a"), &ledger).unwrap();
    assert_eq!(answer.text, "fine");
    assert_eq!(answer.attempts, 2);
    assert_eq!(server.requests().len(), 2);
    let summary = ledger.summary();
    assert_eq!((summary.total.calls, summary.total.retries), (1, 1));
}

#[test]
fn server_error_then_success() {
    let server = server(vec![Reply::text(500, "internal error"), ok("fine")]);
    let answer = client(config(&server))
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    assert_eq!((answer.text.as_str(), answer.attempts), ("fine", 2));
}

#[test]
fn server_errors_until_the_attempts_run_out() {
    let server = server(vec![Reply::json(
        503,
        json!({"error": {"message": "overloaded"}}),
    )]);
    let ledger = CostLedger::unlimited();
    let error = client(config(&server))
        .complete(&request("a"), &ledger)
        .unwrap_err();
    let LvlmError::GaveUp { attempts, .. } = &error else {
        panic!("{error}");
    };
    assert_eq!(*attempts, 3);
    let message = error.to_string();
    assert!(message.contains("after 3 attempt(s)"), "{message}");
    assert!(message.contains("HTTP 503: overloaded"), "{message}");
    assert_eq!(server.requests().len(), 3);
    let summary = ledger.summary();
    assert_eq!((summary.total.retries, summary.total.failures), (2, 1));
    assert_eq!(summary.total.cost_usd, 0.0);
}

#[test]
fn a_hung_server_times_out_and_the_retry_succeeds() {
    let server = server(vec![Reply::fault(Fault::Hang), ok("after the hang")]);
    let config = LvlmConfig {
        request_timeout_secs: 0.3,
        ..config(&server)
    };
    let answer = client(config)
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    assert_eq!(
        (answer.text.as_str(), answer.attempts),
        ("after the hang", 2)
    );
}

#[test]
fn only_hangs_give_up_saying_it_timed_out() {
    let server = server(vec![Reply::fault(Fault::Hang)]);
    let config = LvlmConfig {
        request_timeout_secs: 0.2,
        max_attempts: 2,
        ..config(&server)
    };
    let error = client(config)
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, LvlmError::GaveUp { attempts: 2, .. }),
        "{message}"
    );
    assert!(message.contains("timed out"), "{message}");
}

#[test]
fn a_truncated_body_is_retried() {
    let truncated = Reply {
        fault: Some(Fault::Truncate { keep_bytes: 40 }),
        ..ok("lost")
    };
    let server = server(vec![truncated, ok("whole")]);
    let ledger = CostLedger::unlimited();
    let answer = client(config(&server))
        .complete(&request("a"), &ledger)
        .unwrap();
    assert_eq!((answer.text.as_str(), answer.attempts), ("whole", 2));
    assert_eq!(ledger.summary().total.retries, 1);
}

#[test]
fn a_closed_connection_is_retried() {
    let server = server(vec![Reply::fault(Fault::CloseWithoutReply), ok("second")]);
    let answer = client(config(&server))
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    assert_eq!((answer.text.as_str(), answer.attempts), ("second", 2));
}

#[test]
fn a_malformed_body_is_retried_and_reported() {
    let server = server(vec![Reply::text(200, "{\"choices\": [{\"message\": ")]);
    let error = client(config(&server))
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, LvlmError::GaveUp { attempts: 3, .. }),
        "{message}"
    );
    assert!(
        message.contains("malformed response") && message.contains("not JSON"),
        "{message}"
    );
    assert_eq!(server.requests().len(), 3);
}

#[test]
fn a_body_without_content_is_charged_its_usage_and_retried() {
    let no_content = json!({
        "choices": [{"message": {"role": "assistant"}, "finish_reason": "stop"}],
        "usage": {"prompt_tokens": 1000, "completion_tokens": 200},
    });
    let server = server(vec![Reply::json(200, no_content), ok("fine")]);
    let ledger = CostLedger::unlimited();
    let answer = client(config(&server))
        .complete(&request("a"), &ledger)
        .unwrap();
    assert_eq!(answer.attempts, 2);
    // Both attempts were paid for: the failed one reported its usage.
    assert!(
        (answer.cost_usd - 2.0 * EXACT_USD).abs() < 1e-15,
        "{}",
        answer.cost_usd
    );
    let summary = ledger.summary();
    assert_eq!(summary.total.prompt_tokens, 2000);
    assert!((summary.total.cost_usd - 2.0 * EXACT_USD).abs() < 1e-15);
}

#[test]
fn a_bad_request_is_not_retried() {
    let server = server(vec![Reply::json(
        400,
        json!({"error": {"message": "Invalid image_url", "type": "invalid_request_error"}}),
    )]);
    let ledger = CostLedger::unlimited();
    let error = client(config(&server))
        .complete(&request("a"), &ledger)
        .unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, LvlmError::Refused { status: 400, .. }),
        "{message}"
    );
    assert!(message.contains("Invalid image_url"), "{message}");
    assert_eq!(server.requests().len(), 1);
    assert_eq!(ledger.summary().total.failures, 1);
}

#[test]
fn a_wrong_key_names_the_variable_to_check_and_is_not_retried() {
    let server = server(vec![Reply::json(
        401,
        json!({"error": {"message": "Incorrect API key provided"}}),
    )]);
    let error = client(config(&server))
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap_err();
    let message = error.to_string();
    assert!(message.contains("answered 401"), "{message}");
    assert!(message.contains("UNIPHYS_LVLM_API_KEY"), "{message}");
    assert!(!message.contains(KEY), "{message}");
    assert_eq!(server.requests().len(), 1);
}

#[test]
fn a_cache_hit_sends_nothing_and_costs_nothing() {
    let server = server(vec![ok("cached answer")]);
    let cache = Arc::new(MemoryCache::new());
    let client = client_with_cache(config(&server), cache.clone());
    let ledger = CostLedger::unlimited();
    let first = client.complete(&request("same"), &ledger).unwrap();
    let second = client.complete(&request("same"), &ledger).unwrap();
    assert!(!first.cached && second.cached);
    assert_eq!(second.text, "cached answer");
    assert_eq!((second.cost_usd, second.attempts), (0.0, 0));
    assert_eq!(second.digest, first.digest);
    assert_eq!(server.requests().len(), 1);
    let summary = ledger.summary();
    assert_eq!((summary.total.calls, summary.total.cache_hits), (1, 1));
    assert!((summary.total.cost_usd - EXACT_USD).abs() < 1e-15);

    // A different request is not a hit; a forgotten answer is asked again.
    client.complete(&request("other"), &ledger).unwrap();
    assert_eq!(server.requests().len(), 2);
    client.forget(&first.digest).unwrap();
    let again = client.complete(&request("same"), &ledger).unwrap();
    assert!(!again.cached);
    assert_eq!(server.requests().len(), 3);
}

#[test]
fn a_directory_cache_survives_a_new_client_so_a_stage_retry_does_not_pay_twice() {
    let server = server(vec![ok("remembered")]);
    let dir = tempfile::tempdir().unwrap();
    {
        let cache = Arc::new(DirCache::new(dir.path()).unwrap());
        let client = client_with_cache(config(&server), cache);
        client
            .complete(&request("a"), &CostLedger::unlimited())
            .unwrap();
    }
    let cache = Arc::new(DirCache::new(dir.path()).unwrap());
    let client = client_with_cache(config(&server), cache);
    let retry_ledger = CostLedger::unlimited();
    let answer = client.complete(&request("a"), &retry_ledger).unwrap();
    assert!(answer.cached);
    assert_eq!(answer.text, "remembered");
    assert_eq!(server.requests().len(), 1);
    assert_eq!(retry_ledger.spent_usd(), 0.0);
}

#[test]
fn the_key_is_never_in_the_cache_files() {
    let server = server(vec![ok("answer")]);
    let dir = tempfile::tempdir().unwrap();
    let cache = Arc::new(DirCache::new(dir.path()).unwrap());
    let client = client_with_cache(config(&server), cache);
    let answer = client
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    let mut files = 0;
    for entry in std::fs::read_dir(dir.path()).unwrap() {
        let text = std::fs::read_to_string(entry.unwrap().path()).unwrap();
        assert!(!text.contains(KEY), "{text}");
        assert!(text.contains("answer"));
        files += 1;
    }
    assert_eq!(files, 1);
    assert!(dir.path().join(format!("{}.json", answer.digest)).exists());
}

#[test]
fn the_budget_refuses_before_anything_is_sent() {
    let server = server(vec![ok("never")]);
    // The estimate is at least max_completion_tokens (1000) x 10 USD / M = 0.01 USD.
    let ledger = CostLedger::new(Some(0.005));
    let error = client(config(&server))
        .complete(&request("a"), &ledger)
        .unwrap_err();
    let LvlmError::BudgetExceeded {
        spent_usd,
        budget_usd,
        estimated_usd,
    } = error
    else {
        panic!("{error}");
    };
    assert_eq!((spent_usd, budget_usd), (0.0, 0.005));
    assert!(estimated_usd >= 0.01, "{estimated_usd}");
    assert!(server.requests().is_empty());
    assert_eq!(ledger.summary().total.refused_for_budget, 1);
}

#[test]
fn the_budget_stops_an_asset_once_spending_reaches_it() {
    let server = server(vec![ok("paid")]);
    // Room for one estimated call (about 0.0103 USD) but not for a second after paying 0.00325.
    let ledger = CostLedger::new(Some(0.012));
    let client = client(config(&server));
    client.complete(&request("first"), &ledger).unwrap();
    let error = client.complete(&request("second"), &ledger).unwrap_err();
    assert!(matches!(error, LvlmError::BudgetExceeded { .. }), "{error}");
    assert_eq!(server.requests().len(), 1);
    assert!((ledger.spent_usd() - EXACT_USD).abs() < 1e-15);
}

#[test]
fn concurrency_stays_within_the_limit_with_sixteen_threads() {
    let server = server(vec![ok("slow").with_delay_ms(40)]);
    let client = Arc::new(client(LvlmConfig {
        max_concurrency: 4,
        ..config(&server)
    }));
    let ledger = Arc::new(CostLedger::unlimited());
    let threads: Vec<_> = (0..16)
        .map(|i| {
            let (client, ledger) = (Arc::clone(&client), Arc::clone(&ledger));
            std::thread::spawn(move || client.complete(&request(&format!("part {i}")), &ledger))
        })
        .collect();
    for thread in threads {
        assert_eq!(thread.join().unwrap().unwrap().text, "slow");
    }
    assert_eq!(server.requests().len(), 16);
    let peak = server.max_in_flight();
    assert!(peak <= 4, "{peak} requests in flight");
    assert!(
        peak >= 2,
        "requests were not sent concurrently (peak {peak})"
    );
    assert_eq!(ledger.summary().total.calls, 16);
    assert_eq!(client.in_flight(), 0);
}

/// Counts the tokens it grants.
#[derive(Default)]
struct CountingLimiter(AtomicUsize);

impl RateLimiter for CountingLimiter {
    fn acquire(&self) -> Result<(), LvlmError> {
        self.0.fetch_add(1, Ordering::SeqCst);
        Ok(())
    }
}

#[test]
fn the_rate_limiter_is_asked_before_every_attempt() {
    let server = server(vec![Reply::text(502, "bad gateway"), ok("fine")]);
    let limiter = Arc::new(CountingLimiter::default());
    let client = LvlmClient::new(config(&server), limiter.clone(), Arc::new(NoCache)).unwrap();
    client
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    assert_eq!(limiter.0.load(Ordering::SeqCst), 2);
}

/// Refuses every token, as a fleet-wide limiter that lost its store might.
struct BrokenLimiter;

impl RateLimiter for BrokenLimiter {
    fn acquire(&self) -> Result<(), LvlmError> {
        Err(LvlmError::RateLimiter {
            reason: "redis unreachable".to_owned(),
        })
    }
}

#[test]
fn a_failing_rate_limiter_stops_the_request_before_sending() {
    let server = server(vec![ok("never")]);
    let client =
        LvlmClient::new(config(&server), Arc::new(BrokenLimiter), Arc::new(NoCache)).unwrap();
    let error = client
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap_err();
    assert!(error.to_string().contains("redis unreachable"), "{error}");
    assert!(server.requests().is_empty());
}

#[test]
fn an_answer_with_json_outside_the_markers_reaches_the_caller_for_the_stage_to_judge() {
    let server = server(vec![ok("Sure! {\"object_name\": \"mug\"}")]);
    let answer = client(config(&server))
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    let error = extract_marked_json(&answer.text).unwrap_err();
    assert!(
        matches!(
            error,
            LvlmError::NoJsonMarkers {
                json_outside_markers: true,
                ..
            }
        ),
        "{error}"
    );
}

#[test]
fn retry_after_is_waited_for_up_to_the_backoff_cap() {
    // Retry-After asks for 5 s; the cap is 0.25 s; without Retry-After the backoff would be
    // about 1 ms. The gap between the two requests shows which wait the client chose.
    let arrivals = Arc::new(std::sync::Mutex::new(Vec::new()));
    let seen = Arc::clone(&arrivals);
    let server = ReplayServer::start_with(Arc::new(move |_request: &RecordedRequest| {
        let mut seen = seen.lock().unwrap();
        seen.push(std::time::Instant::now());
        if seen.len() == 1 {
            Reply::text(429, "slow down").with_header("Retry-After", "5")
        } else {
            ok("fine")
        }
    }))
    .unwrap();
    let config = LvlmConfig {
        backoff_max_secs: 0.25,
        ..config(&server)
    };
    let answer = client(config)
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap();
    assert_eq!(answer.attempts, 2);
    let arrivals = arrivals.lock().unwrap();
    let gap = arrivals[1].duration_since(arrivals[0]);
    assert!(gap >= std::time::Duration::from_millis(250), "{gap:?}");
}

#[test]
fn a_model_refusal_is_reported_and_not_retried() {
    let refusal = json!({
        "choices": [{"message": {"role": "assistant", "content": null, "refusal": "I can't help with that."}}],
        "usage": {"prompt_tokens": 1000, "completion_tokens": 200},
    });
    let server = server(vec![Reply::json(200, refusal)]);
    let ledger = CostLedger::unlimited();
    let error = client(config(&server))
        .complete(&request("a"), &ledger)
        .unwrap_err();
    assert!(matches!(error, LvlmError::ModelRefused { .. }), "{error}");
    assert!(error.to_string().contains("I can't help"), "{error}");
    assert_eq!(server.requests().len(), 1);
    // The refusal was paid for.
    assert!((ledger.spent_usd() - EXACT_USD).abs() < 1e-15);
}

#[test]
fn an_unreachable_server_gives_up_saying_so() {
    let port = {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        listener.local_addr().unwrap().port()
    };
    let config = LvlmConfig {
        base_url: format!("http://127.0.0.1:{port}/v1"),
        max_attempts: 2,
        backoff_initial_secs: 0.001,
        backoff_max_secs: 0.01,
        ..LvlmConfig::default()
    };
    let error = client(config)
        .complete(&request("a"), &CostLedger::unlimited())
        .unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, LvlmError::GaveUp { attempts: 2, .. }),
        "{message}"
    );
    assert!(message.contains("cannot reach"), "{message}");
}
