use std::time::Duration;

use crate::Failure;

/// Everything that can go wrong sending a request under a [`crate::RetryPolicy`]. Clients map it
/// into their own error, adding what the request was for.
#[derive(Debug, thiserror::Error)]
pub enum HttpError {
    /// A setting is outside its valid range.
    #[error("invalid HTTP option {name} = {value}: expected {expected}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// The HTTP client cannot be built (TLS backend or resolver configuration).
    #[error("cannot build the HTTP client: {reason}")]
    Build {
        /// The client's error.
        reason: String,
    },
    /// An attempt failed in a way retrying would not change (a refusing status, an answer that
    /// cannot be used, a request that cannot be sent).
    #[error("{failure}")]
    Permanent {
        /// What went wrong.
        failure: Failure,
    },
    /// Every attempt allowed failed transiently, or the next wait would pass the deadline.
    #[error(
        "gave up after {attempts} attempt(s) in {} ms{}: {last}",
        elapsed.as_millis(),
        if *deadline_passed { " (the overall deadline would pass before the next attempt)" } else { "" }
    )]
    GaveUp {
        /// Attempts made.
        attempts: u32,
        /// Time from the first attempt to giving up.
        elapsed: Duration,
        /// Whether the deadline, not the attempt count, stopped the retries.
        deadline_passed: bool,
        /// The last attempt's failure (its status, if it had one).
        last: Failure,
    },
}

/// Result alias of this crate.
pub type HttpResult<T> = Result<T, HttpError>;
