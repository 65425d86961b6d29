//! The crate's error type.

/// Errors raised while normalising evaluation inputs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// A member id was not an integer, an integral float or a non-empty string.
    #[error("invalid member id: {0}")]
    InvalidId(String),
}
