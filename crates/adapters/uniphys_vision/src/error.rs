use std::time::Duration;

/// Everything that can go wrong talking to a SAM-compatible or PartField-compatible service.
/// Each message names the service and says what was wrong.
#[derive(Debug, thiserror::Error)]
pub enum VisionError {
    /// A client setting is outside its valid range.
    #[error("invalid {service} client option {name} = {value}: {expected}")]
    InvalidOption {
        /// Service name (`"sam"`, `"partfield"`).
        service: &'static str,
        /// Option name.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// The input cannot be sent (empty mesh, index out of range, not a PNG of the stated size).
    #[error("cannot ask the {service} service: {reason}")]
    InvalidInput {
        /// Service name.
        service: &'static str,
        /// What is wrong with the input.
        reason: String,
    },
    /// Every attempt failed with a retryable error (connection, timeout, 408, 425, 429, 500,
    /// 502, 503, 504, truncated or malformed body).
    #[error(
        "{service} request {path} failed after {attempts} attempt(s): {reason}; check that the service at {base_url} is up"
    )]
    GaveUp {
        /// Service name.
        service: &'static str,
        /// Request path.
        path: &'static str,
        /// Base URL of the service.
        base_url: String,
        /// Attempts made.
        attempts: u32,
        /// The last failure.
        reason: String,
    },
    /// The service refused the request with a status retrying would not change (a 4xx other
    /// than 408/425/429, or 501, 505 and up).
    #[error("{service} request {path} was refused with HTTP {status}: {message}")]
    Refused {
        /// Service name.
        service: &'static str,
        /// Request path.
        path: &'static str,
        /// HTTP status.
        status: u16,
        /// The server's message (its JSON `error`/`detail`/`message`, else the start of the body).
        message: String,
    },
    /// The answer is valid JSON but breaks the contract (`proto/vision.openapi.yaml`): wrong
    /// fields, RLE of the wrong size, feature count or non-finite values. Not retried.
    #[error("{service} answer to {path} breaks the contract: {reason}")]
    InvalidAnswer {
        /// Service name.
        service: &'static str,
        /// Request path.
        path: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The HTTP client failed in a way retrying cannot fix (bad URL, unsupported scheme, an
    /// answer larger than `max_response_bytes`).
    #[error("{service} request to {url} cannot be sent: {reason}")]
    Transport {
        /// Service name.
        service: &'static str,
        /// The URL.
        url: String,
        /// The client's error.
        reason: String,
    },
    /// The health check did not answer 2xx within the timeout.
    #[error("{service} service at {base_url} is not healthy within {timeout:?}: {reason}")]
    Unhealthy {
        /// Service name.
        service: &'static str,
        /// Base URL.
        base_url: String,
        /// The request timeout.
        timeout: Duration,
        /// What happened.
        reason: String,
    },
}

/// Result alias of this crate.
pub type VisionResult<T> = Result<T, VisionError>;
