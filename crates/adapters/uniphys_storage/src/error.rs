/// Errors of artifact storage.
#[derive(Debug, thiserror::Error)]
pub enum StorageError {
    /// The object store failed.
    #[error("object store error at {key}: {source}")]
    Store {
        /// The key being accessed.
        key: String,
        /// The underlying error.
        #[source]
        source: object_store::Error,
    },
    /// A local directory could not be created.
    #[error("could not create storage directory {path}: {source}")]
    CreateDir {
        /// The directory.
        path: String,
        /// The IO error.
        #[source]
        source: std::io::Error,
    },
    /// A key contained a component that is not allowed (empty, `.`/`..`, or a control character).
    #[error("invalid artifact key {0:?}: components must be non-empty and must not be . or ..")]
    InvalidKey(String),
}

/// Result alias for [`StorageError`].
pub type StorageResult<T> = Result<T, StorageError>;
