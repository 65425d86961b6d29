//! Blocking client of OpenAI-compatible chat-completions servers with image inputs, for the
//! LVLM annotation stage (reference sections 5 and 9, done more robustly: bounded concurrency,
//! fleet-wide rate limits, timeouts, retries with backoff, cost accounting with a budget, and an
//! answer cache so a retried stage does not pay twice).
//!
//! Flow: a [`ChatRequest`] (system prompt, user text, PNG images) → [`LvlmClient::complete`]
//! (cache → budget → concurrency permit → [`RateLimiter`] → POST `/chat/completions` → retries)
//! → [`ChatAnswer`], charged to a per-asset [`CostLedger`]; [`extract_marked_json`] takes the
//! JSON between `===BEGIN_JSON===` and `===END_JSON===` out of the answer. Schema validation and
//! re-asking live in the stage (`uniphys_annotate`).
//!
//! The API key comes from the caller (conventionally [`API_KEY_VARIABLE`]); it is sent only in
//! the `Authorization` header, never hashed into the cache key, cached or printed.

mod cache;
mod client;
mod config;
mod error;
mod extract;
mod ledger;
mod permits;
mod rate_limit;
mod request;
mod response;

pub use cache::{AnswerCache, CachedAnswer, DirCache, MemoryCache, NoCache};
pub use client::{ChatAnswer, LvlmClient};
pub use config::{API_KEY_VARIABLE, LvlmConfig, Pricing};
pub use error::{LvlmError, LvlmResult};
pub use extract::{BEGIN_JSON_MARKER, END_JSON_MARKER, extract_marked_json};
pub use ledger::{
    COMPLETION_TOKENS_ESTIMATE, CostLedger, IMAGE_TOKENS_FALLBACK, LedgerSummary, PurposeSummary,
    estimate_prompt_tokens, image_tokens_estimate,
};
pub use permits::{Permit, Permits};
pub use rate_limit::{LocalTokenBucket, NoRateLimit, RateLimiter};
pub use request::{ChatRequest, RequestBody};
pub use response::{ChatResponse, Usage, parse_chat_response};
