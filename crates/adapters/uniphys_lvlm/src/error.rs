use std::path::PathBuf;

/// Everything that can go wrong talking to an LVLM server. Each message says what is wrong and
/// what to do about it; none contains the API key.
#[derive(Debug, thiserror::Error)]
pub enum LvlmError {
    /// A configuration value is outside its valid range.
    #[error("invalid LVLM option {name} = {value}: expected {expected}")]
    InvalidConfig {
        /// Option name.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// The request cannot be sent as built (for example an image that is not a PNG).
    #[error("invalid LVLM request ({purpose}): {reason}")]
    InvalidRequest {
        /// What the request was for.
        purpose: String,
        /// What is wrong.
        reason: String,
    },
    /// Sending the request could exceed the asset's budget; nothing was sent.
    #[error(
        "LVLM budget exceeded: {spent_usd:.6} USD spent or in flight, this request is estimated at {estimated_usd:.6} USD, the budget is {budget_usd:.6} USD; raise the budget or annotate fewer parts"
    )]
    BudgetExceeded {
        /// Spent so far on this asset, calls in flight included.
        spent_usd: f64,
        /// The asset's budget.
        budget_usd: f64,
        /// Estimate of the refused request.
        estimated_usd: f64,
    },
    /// The server rejected the credentials (HTTP 401 or 403).
    #[error(
        "the LVLM server answered {status}: {message}; check the API key (read by the caller from {key_variable}) and that it may use the configured model"
    )]
    Unauthorized {
        /// HTTP status.
        status: u16,
        /// The server's error message.
        message: String,
        /// The environment variable the key is conventionally read from.
        key_variable: &'static str,
    },
    /// The server refused the request (a status retrying would not change: a 4xx other than
    /// 408/425/429, or 501, 505 and up).
    #[error(
        "the LVLM server refused the {purpose} request with HTTP {status}: {message}; check the model name, the base URL and the request options"
    )]
    Refused {
        /// What the request was for.
        purpose: String,
        /// HTTP status.
        status: u16,
        /// The server's error message (or the start of its body).
        message: String,
    },
    /// The model declined to answer (an OpenAI `refusal`); asking again would not help.
    #[error("the model declined the {purpose} request: {message}; review the prompt and images")]
    ModelRefused {
        /// What the request was for.
        purpose: String,
        /// The model's refusal text.
        message: String,
    },
    /// Every attempt failed with a retryable error (408, 425, 429, 500, 502, 503, 504, timeout,
    /// connection, truncated or malformed body).
    #[error(
        "LVLM {purpose} request failed after {attempts} attempt(s); last failure: {last_failure}; check that the server at the configured base URL is up and not overloaded, or raise max_attempts / request_timeout_secs"
    )]
    GaveUp {
        /// What the request was for.
        purpose: String,
        /// Attempts made.
        attempts: u32,
        /// The last attempt's failure.
        last_failure: String,
    },
    /// A response body is not a chat completion (or lacks the parts the client needs).
    #[error(
        "malformed chat-completions response: {what}; the server does not follow the OpenAI chat-completions format"
    )]
    Malformed {
        /// What is missing or wrong.
        what: String,
    },
    /// The answer has no `===BEGIN_JSON===` marker.
    #[error("{}", no_markers_message(*json_outside_markers, excerpt))]
    NoJsonMarkers {
        /// Whether the text contains a JSON value outside the markers.
        json_outside_markers: bool,
        /// Start of the answer.
        excerpt: String,
    },
    /// `===BEGIN_JSON===` without a following `===END_JSON===`.
    #[error(
        "the model's answer opens ===BEGIN_JSON=== but never closes it with ===END_JSON=== (the answer was probably cut off; raise max_completion_tokens or ask again); it ends with: {excerpt:?}"
    )]
    UnterminatedJson {
        /// End of the answer.
        excerpt: String,
    },
    /// The text between the markers is not valid JSON.
    #[error(
        "the JSON between the markers is not valid: {message} (line {line}, column {column}); it starts with: {excerpt:?}"
    )]
    InvalidJson {
        /// The parser's message.
        message: String,
        /// 1-based line inside the marked text.
        line: usize,
        /// 1-based column inside the marked text.
        column: usize,
        /// Start of the marked text.
        excerpt: String,
    },
    /// The rate limiter could not grant a request.
    #[error("the LVLM rate limiter failed: {reason}")]
    RateLimiter {
        /// What went wrong.
        reason: String,
    },
    /// Reading or writing the answer cache failed.
    #[error(
        "LVLM answer cache at {path}: {source}; check that the directory exists and is writable"
    )]
    Cache {
        /// The file or directory.
        path: PathBuf,
        /// The IO error.
        source: std::io::Error,
    },
    /// Encoding a request or cache entry as JSON failed.
    #[error("cannot encode {what} as JSON: {source}")]
    Encode {
        /// What was being encoded.
        what: &'static str,
        /// The serde error.
        source: serde_json::Error,
    },
}

fn no_markers_message(json_outside_markers: bool, excerpt: &str) -> String {
    if json_outside_markers {
        format!(
            "the model's answer has no ===BEGIN_JSON=== marker, but there is JSON outside the markers (the model ignored the output format); ask again or repair the answer; it starts with: {excerpt:?}"
        )
    } else {
        format!(
            "the model's answer has no ===BEGIN_JSON=== marker and no JSON at all; ask again; it starts with: {excerpt:?}"
        )
    }
}

/// Result alias of this crate.
pub type LvlmResult<T> = Result<T, LvlmError>;

impl LvlmError {
    /// Whether asking the model again (a new request, or the same one later) may succeed:
    /// transport failures and answers that did not follow the output format.
    #[must_use]
    pub fn is_transient(&self) -> bool {
        matches!(
            self,
            Self::GaveUp { .. }
                | Self::Malformed { .. }
                | Self::NoJsonMarkers { .. }
                | Self::UnterminatedJson { .. }
                | Self::InvalidJson { .. }
        )
    }
}

/// The first `max_chars` characters of `text`, with `...` when cut (the shared client's).
pub(crate) use uniphys_http::excerpt;

/// The last `max_chars` characters of `text`, with `...` in front when cut.
pub(crate) fn tail_excerpt(text: &str, max_chars: usize) -> String {
    let count = text.chars().count();
    if count <= max_chars {
        return text.to_owned();
    }
    let tail: String = text.chars().skip(count - max_chars).collect();
    format!("...{tail}")
}
