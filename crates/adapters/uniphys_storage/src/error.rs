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
    /// No object is stored at the key.
    #[error("no artifact at {key}")]
    NotFound {
        /// The key that was read.
        key: String,
    },
    /// A create-only write found different content already stored under the key. The stored
    /// object is left unchanged.
    #[error("artifact {key} already exists with different content")]
    Conflict {
        /// The key that was written.
        key: String,
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
    /// A local file being uploaded or downloaded could not be read or written.
    #[error("local file {path}: {source}")]
    LocalFile {
        /// The local file.
        path: String,
        /// The IO error.
        #[source]
        source: std::io::Error,
    },
    /// A key contained a component that is not allowed (empty, `.`/`..`, or a control character).
    #[error("invalid artifact key {0:?}: components must be non-empty and must not be . or ..")]
    InvalidKey(String),
    /// A storage URL could not be understood.
    #[error("invalid storage URL {url:?}: {reason}")]
    InvalidUrl {
        /// The URL as given.
        url: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A storage option (e.g. from the environment) had a value that could not be parsed.
    #[error("invalid storage option {name}={value:?}: {reason}")]
    InvalidOption {
        /// The option's name.
        name: String,
        /// The value as given.
        value: String,
        /// What is wrong with it.
        reason: String,
    },
}

impl StorageError {
    /// Wraps an `object_store` error at `key`, turning "not found" into [`StorageError::NotFound`].
    pub(crate) fn from_store(key: &str, source: object_store::Error) -> Self {
        match source {
            object_store::Error::NotFound { .. } => Self::NotFound {
                key: key.to_owned(),
            },
            source => Self::Store {
                key: key.to_owned(),
                source,
            },
        }
    }
}

/// Result alias for [`StorageError`].
pub type StorageResult<T> = Result<T, StorageError>;
