/// Errors of the export stage.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The asset record broke an invariant.
    #[error("invalid asset record: {0}")]
    InvalidRecord(#[from] uniphys_types::TypesError),
    /// The inputs do not fit together (e.g. fewer meshes than parts).
    #[error("export inputs do not match: {0}")]
    InputMismatch(String),
    /// A file of an earlier export could not be read back.
    #[error("cannot read {path} of the earlier export: {message}")]
    Unreadable {
        /// Path in the export's folder.
        path: String,
        /// What is wrong with it.
        message: String,
    },
    /// A JSON document could not be serialised.
    #[error("could not serialise {path}: {message}")]
    Json {
        /// Artifact path.
        path: String,
        /// Serializer message.
        message: String,
    },
}

/// Result alias for [`ExportError`].
pub type ExportResult<T> = Result<T, ExportError>;
