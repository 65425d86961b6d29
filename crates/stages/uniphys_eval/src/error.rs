//! The crate's error type.

use std::path::PathBuf;

/// Errors raised while normalising or loading evaluation inputs.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// A member id was not an integer, an integral float or a non-empty string.
    #[error("invalid member id: {0}")]
    InvalidId(String),
    /// A file or directory could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A JSON file is not what it should be.
    #[error("{} is not a valid {what}: {message}", path.display())]
    Json {
        /// The path.
        path: PathBuf,
        /// What the file should hold (`record.json`, `UniPhys-40K part record`).
        what: &'static str,
        /// The parser's message.
        message: String,
    },
    /// The ground-truth URDF could not be ingested.
    #[error("cannot load the ground truth {}: {source}", path.display())]
    Ingest {
        /// The path.
        path: PathBuf,
        /// The ingest error.
        source: uniphys_mesh_io::IngestError,
    },
    /// A part's mesh file (`parts/part_<id>.obj` of an output directory) could not be read.
    #[error("cannot read the part mesh {}: {source}", path.display())]
    PartMesh {
        /// The path.
        path: PathBuf,
        /// The ingest error.
        source: uniphys_mesh_io::IngestError,
    },
    /// A path is none of the accepted inputs.
    #[error("{} is not {expected}", path.display())]
    UnrecognisedInput {
        /// The path.
        path: PathBuf,
        /// What was accepted there.
        expected: &'static str,
    },
    /// Predictions and ground truths cannot be paired.
    #[error("{0}")]
    Mismatch(String),
}

/// Result alias of the crate.
pub type EvalResult<T> = Result<T, EvalError>;
