//! The crate's error type.

/// Why an archive was refused, or could not be read or unpacked.
#[derive(Debug, thiserror::Error)]
pub enum ArchiveError {
    /// The archive cannot be read as the kind its name says (truncated, corrupt, encrypted).
    #[error("the archive cannot be read: {0}")]
    Unreadable(String),
    /// An entry that would be unsafe to unpack (a path out of the asset's folder, a link, a
    /// device) or that clashes with another one.
    #[error("entry {entry:?} is refused: {reason}")]
    UnsafeEntry {
        /// The entry's name as stored.
        entry: String,
        /// What is wrong with it.
        reason: String,
    },
    /// More entries or more unpacked bytes than the limits allow.
    #[error("{0}")]
    TooLarge(String),
    /// No file the pipeline reads, or several that could each be the asset.
    #[error("{0}")]
    NoAsset(String),
    /// Local disk (the archive file, the folder unpacked into, the folder packed).
    #[error("{context}: {source}")]
    Io {
        /// What was being done.
        context: String,
        /// The error.
        source: std::io::Error,
    },
}

impl ArchiveError {
    /// Whether the archive itself is at fault (the submitter must change it), as opposed to the
    /// local disk.
    #[must_use]
    pub fn is_refusal(&self) -> bool {
        !matches!(self, Self::Io { .. })
    }

    pub(crate) fn io(context: impl Into<String>) -> impl FnOnce(std::io::Error) -> Self {
        let context = context.into();
        move |source| Self::Io { context, source }
    }
}

/// Result alias of this crate.
pub type ArchiveResult<T> = Result<T, ArchiveError>;
