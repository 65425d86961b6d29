//! Shared helpers of the stage tests: the box-with-lid example, recorded answers, a client for a
//! local replay server.
#![allow(dead_code)]

use std::path::Path;
use std::sync::Arc;

use serde_json::{Value, json};
use uniphys_annotate::AnnotateOptions;
use uniphys_geometry::TriMesh;
use uniphys_lvlm::{AnswerCache, LvlmClient, LvlmConfig, NoRateLimit};

pub const MODEL: &str = "test-model";
pub const PROMPT_TOKENS: u64 = 1000;
pub const COMPLETION_TOKENS: u64 = 200;

pub fn fixture(name: &str) -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).expect("json")
}

/// The answer text: the JSON between the markers, with some prose around it.
pub fn marked(value: &Value) -> String {
    format!("Here is the annotation.\n===BEGIN_JSON===\n{value:#}\n===END_JSON===\n")
}

/// A chat-completions response body with `text` and fixed token usage.
pub fn completion(text: &str) -> Value {
    json!({
        "id": "chatcmpl-test", "object": "chat.completion", "created": 0, "model": MODEL,
        "choices": [{"index": 0, "finish_reason": "stop",
                     "message": {"role": "assistant", "content": text}}],
        "usage": {"prompt_tokens": PROMPT_TOKENS, "completion_tokens": COMPLETION_TOKENS,
                  "total_tokens": PROMPT_TOKENS + COMPLETION_TOKENS}
    })
}

/// USD of one call at the default prices (1.25 in, 10 out per million tokens).
pub fn call_cost_usd() -> f64 {
    (PROMPT_TOKENS as f64 * 1.25 + COMPLETION_TOKENS as f64 * 10.0) / 1e6
}

pub struct BoxWithLid {
    pub meshes: Vec<TriMesh>,
    pub colours: Vec<[f32; 4]>,
    pub names: Vec<String>,
}

pub fn box_with_lid() -> BoxWithLid {
    let example = uniphys_examples::example("box_with_lid").expect("example");
    BoxWithLid {
        meshes: example.asset.parts.iter().map(|p| p.mesh.clone()).collect(),
        colours: vec![[0.6, 0.4, 0.2, 1.0], [0.8, 0.6, 0.3, 1.0]],
        names: example.asset.parts.iter().map(|p| p.name.clone()).collect(),
    }
}

pub fn options() -> AnnotateOptions {
    AnnotateOptions {
        panel_px: 64,
        points_per_part: 400,
        ..AnnotateOptions::default()
    }
}

pub fn config(url: &str) -> LvlmConfig {
    LvlmConfig {
        base_url: format!("{url}/v1"),
        model: MODEL.to_owned(),
        reasoning_effort: None,
        request_timeout_secs: 5.0,
        max_attempts: 4,
        backoff_initial_secs: 0.01,
        backoff_max_secs: 0.05,
        max_concurrency: 4,
        ..LvlmConfig::default()
    }
}

pub fn client(config: LvlmConfig, cache: Arc<dyn AnswerCache>) -> LvlmClient {
    LvlmClient::new(config, Arc::new(NoRateLimit), cache).expect("client")
}

/// Which request a body is.
pub fn is_properties(body: &str) -> bool {
    body.contains("UniPhys properties prompt")
}

pub fn is_repair(body: &str) -> bool {
    body.contains("Your previous answer was")
}
