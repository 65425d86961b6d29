//! The crate's one error enum and its `Result` alias.

/// Result of every hints operation.
pub type HintsResult<T> = Result<T, HintsError>;

/// What went wrong in a hints operation.
///
/// Every variant but [`HintsError::InvalidArgument`] and [`HintsError::InvalidUrl`] means "the hint
/// is not available right now": the caller logs it at most once in a while and goes on as if the
/// hint did not exist (poll, run without the fleet-wide limit, skip the progress update).
#[derive(Debug, thiserror::Error)]
pub enum HintsError {
    /// The Redis URL could not be parsed.
    #[error("invalid redis url: {source}")]
    InvalidUrl {
        /// The parse error.
        #[source]
        source: redis::RedisError,
    },
    /// Redis answered with an error, or the connection to it failed.
    #[error("redis {op} failed: {source}")]
    Redis {
        /// The operation: `ring`, `try_acquire`, `acquire_slot`, `set_progress`, ...
        op: &'static str,
        /// The client's error.
        #[source]
        source: redis::RedisError,
    },
    /// Redis did not answer within the operation timeout.
    #[error("redis {op} timed out after {timeout_ms} ms")]
    Timeout {
        /// The operation.
        op: &'static str,
        /// The timeout that ran out.
        timeout_ms: u64,
    },
    /// Redis answered something this crate did not write (a foreign value under our key prefix).
    #[error("unexpected redis reply to {op}: {detail}")]
    UnexpectedReply {
        /// The operation.
        op: &'static str,
        /// What was wrong with it.
        detail: String,
    },
    /// The caller passed a value the operation cannot honour (a rate of 0, more tokens than the
    /// bucket holds, a progress fraction outside 0..=1).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

impl HintsError {
    /// True when the error says the hint store is unreachable or slow (as opposed to a caller
    /// error): the caller should fall back to polling or local behaviour.
    pub fn is_unavailable(&self) -> bool {
        matches!(
            self,
            Self::Redis { .. } | Self::Timeout { .. } | Self::UnexpectedReply { .. }
        )
    }
}
