//! `uniphys run --lvlm-*`: the flags and the key reach the LVLM server (a local replay server
//! answering from the recorded fixtures), and the outputs name the model.

use std::path::Path;
use std::process::Command;
use std::sync::Arc;

use serde_json::{Value, json};
use uniphys_replay::{RecordedRequest, ReplayServer, Reply};

fn fixture(name: &str) -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../stages/uniphys_annotate/tests/fixtures")
        .join(name);
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).expect("json")
}

#[test]
fn run_with_an_lvlm_sends_the_configured_requests_and_records_the_provider() {
    let server = ReplayServer::start_with(Arc::new(|request: &RecordedRequest| {
        let answer = if request.body_text().contains("UniPhys properties prompt") {
            fixture("box_with_lid_properties.json")
        } else {
            fixture("box_with_lid_articulation.json")
        };
        let text = format!("===BEGIN_JSON===\n{answer}\n===END_JSON===");
        Reply::json(
            200,
            json!({"id": "x", "object": "chat.completion", "model": "recorded",
                   "choices": [{"index": 0, "finish_reason": "stop",
                                "message": {"role": "assistant", "content": text}}],
                   "usage": {"prompt_tokens": 100, "completion_tokens": 10, "total_tokens": 110}}),
        )
    }))
    .expect("server");
    let out = tempfile::tempdir().expect("tempdir");
    let asset =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../test_data/examples/box_with_lid.glb");
    let base_url = format!("{}/v1", server.url());
    let cache = out.path().join("cache");
    let output = Command::new(env!("CARGO_BIN_EXE_uniphys"))
        .args(["run", &asset.display().to_string(), "--out"])
        .arg(out.path().join("result"))
        .args(["--lvlm-base-url", &base_url, "--lvlm-model", "recorded"])
        .args(["--lvlm-reasoning-effort", "none", "--lvlm-concurrency", "2"])
        .args(["--lvlm-budget-usd", "0.5", "--lvlm-cache-dir"])
        .arg(&cache)
        .env("UNIPHYS_LVLM_API_KEY", "sk-test-key")
        .env_remove("OPENAI_API_KEY")
        .output()
        .expect("run uniphys");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        matches!(output.status.code(), Some(0 | 1)),
        "the run failed: {stderr}"
    );
    let requests = server.requests();
    assert_eq!(requests.len(), 2, "{stderr}");
    for request in &requests {
        assert_eq!(
            request.headers.get("authorization").map(String::as_str),
            Some("Bearer sk-test-key")
        );
        let body: Value = serde_json::from_slice(&request.body).expect("json body");
        assert_eq!(body["model"], "recorded");
        assert!(body.get("reasoning_effort").is_none(), "none leaves it out");
    }
    assert!(std::fs::read_dir(&cache).expect("cache dir").count() >= 2);
    let record: Value = serde_json::from_str(
        &std::fs::read_to_string(out.path().join("result/record.json")).expect("record"),
    )
    .expect("json");
    assert_eq!(record["object"]["name"]["value"], "wooden box with lid");
    let report = std::fs::read_to_string(out.path().join("result/report.json")).expect("report");
    assert!(
        report.contains("lvlm:recorded"),
        "the notes name the provider"
    );
}
