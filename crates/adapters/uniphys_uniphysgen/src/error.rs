use std::path::PathBuf;
use std::time::Duration;

/// Everything that can go wrong in the UniPhysGen stage. Each message says what is wrong and
/// what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum UniPhysGenError {
    /// The asset has no surface to sample.
    #[error(
        "the asset has no surface area to sample points from (part {part:?}); check that the input has triangles of non-zero area"
    )]
    NoSurface {
        /// The part (or `"object"`) without area.
        part: String,
    },
    /// An option is outside its valid range.
    #[error("invalid option {name} = {value}: {expected}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
    /// The model server could not be reached, or kept failing, after every attempt.
    #[error(
        "UniPhysGen {task} request for sample {sample_id:?} failed after {attempts} attempt(s): {reason}; check that the model server at the configured URL is up"
    )]
    GaveUp {
        /// Task name.
        task: String,
        /// Sample id.
        sample_id: String,
        /// Attempts made.
        attempts: u32,
        /// The last failure.
        reason: String,
    },
    /// The model server did not answer within the request timeout, on the last attempt allowed
    /// (timeouts are retried like other transient failures).
    #[error(
        "UniPhysGen {task} request for sample {sample_id:?} timed out after {timeout:?}; raise the client timeout or check the model server's load"
    )]
    Timeout {
        /// Task name.
        task: String,
        /// Sample id.
        sample_id: String,
        /// The timeout that expired.
        timeout: Duration,
    },
    /// The server refused the request (a status other than 408, 425, 429, 500, 502, 503, 504):
    /// retrying would not help.
    #[error(
        "UniPhysGen {task} request for sample {sample_id:?} was refused with HTTP {status}: {body}; the request does not match the server's contract (proto/uniphysgen/v1)"
    )]
    Refused {
        /// Task name.
        task: String,
        /// Sample id.
        sample_id: String,
        /// HTTP status.
        status: u16,
        /// Start of the response body.
        body: String,
    },
    /// The server's answer is not a valid response of the contract.
    #[error(
        "UniPhysGen {task} response for sample {sample_id:?} is malformed: {reason}; the model server does not follow proto/uniphysgen/v1"
    )]
    MalformedResponse {
        /// Task name.
        task: String,
        /// Sample id.
        sample_id: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A prediction parsed but its values make no sense (restoration refused it).
    #[error("UniPhysGen answer for part {part:?} is invalid: {reason}")]
    InvalidAnswer {
        /// Part id (or `"object"`).
        part: String,
        /// What is wrong.
        reason: String,
    },
    /// No GPU slot became free in time.
    #[error(
        "no UniPhysGen GPU slot became free within {waited:?}; raise the slot limit or the wait, or retry later"
    )]
    NoSlot {
        /// How long the client waited.
        waited: Duration,
    },
    /// Writing an output file failed.
    #[error("cannot write {path}: {source}; check that the directory is writable")]
    Write {
        /// The file.
        path: PathBuf,
        /// The IO error.
        source: std::io::Error,
    },
}

/// Result alias of this crate.
pub type UniPhysGenResult<T> = Result<T, UniPhysGenError>;
