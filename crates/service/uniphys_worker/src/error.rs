//! Errors of the worker library.

/// Why a worker could not start or run.
#[derive(Debug, thiserror::Error)]
pub enum WorkerError {
    /// The configuration cannot work; the message says what to change.
    #[error("worker configuration: {0}")]
    Config(String),
}

/// Result of worker operations.
pub type WorkerResult<T> = Result<T, WorkerError>;
