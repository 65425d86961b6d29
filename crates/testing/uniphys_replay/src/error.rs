use std::path::PathBuf;

/// Everything that can go wrong when loading a recording or starting the replay server.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The recording file cannot be read.
    #[error("cannot read recording {path}: {source}; check the path")]
    Read {
        /// The file.
        path: PathBuf,
        /// The IO error.
        source: std::io::Error,
    },
    /// The recording is not valid JSON of the recording format.
    #[error("recording {origin} is not a valid recording: {source}")]
    Parse {
        /// Where the text came from (a path or `"<string>"`).
        origin: String,
        /// The JSON error.
        source: serde_json::Error,
    },
    /// The recording parses but cannot be played.
    #[error("recording {origin} cannot be played: {reason}")]
    Invalid {
        /// Where the text came from.
        origin: String,
        /// What is wrong.
        reason: String,
    },
    /// The listen address cannot be bound.
    #[error("cannot listen on {address}: {source}; choose another address or port")]
    Bind {
        /// The address asked for.
        address: String,
        /// The IO error.
        source: std::io::Error,
    },
    /// The acceptor thread could not be started.
    #[error("cannot start the replay server's acceptor thread: {0}")]
    Spawn(std::io::Error),
}

/// Result alias of this crate.
pub type ReplayResult<T> = Result<T, ReplayError>;
