//! The crate's one error enum and its `Result` alias.

use crate::ids::StageRunId;

/// Result of every queue operation.
pub type QueueResult<T> = Result<T, QueueError>;

/// What went wrong in a queue operation.
#[derive(Debug, thiserror::Error)]
pub enum QueueError {
    /// A fenced transition (heartbeat, complete, fail) came from a lease that is no longer the
    /// current one: the run was recovered, reclaimed, dead-lettered or finished meanwhile.
    /// The caller must drop its work and never report it again.
    #[error(
        "lease lost on {run_id} attempt {attempt} (now in state {current_state} at attempt {current_attempt})"
    )]
    LeaseLost {
        /// The stage run.
        run_id: StageRunId,
        /// The attempt the caller held.
        attempt: u32,
        /// The attempt the run is at now.
        current_attempt: u32,
        /// The state the run is in now.
        current_state: String,
    },
    /// The run's job was cancelled while the caller held the lease; stop working on it.
    #[error("{run_id} was cancelled")]
    Cancelled {
        /// The stage run.
        run_id: StageRunId,
    },
    /// No such row, or it belongs to another tenant (the two are not told apart).
    #[error("{what} not found: {id}")]
    NotFound {
        /// What was looked up: `job`, `asset`, `stage run`, `tenant`.
        what: &'static str,
        /// The id as displayed.
        id: String,
    },
    /// The operation does not apply to the row's current state (e.g. cancelling a finished job).
    #[error("cannot {action} {id} in state {state}")]
    InvalidTransition {
        /// The requested operation.
        action: &'static str,
        /// The row, as displayed.
        id: String,
        /// Its current state.
        state: String,
    },
    /// A unique value (tenant name, API key) exists already.
    #[error("{what} already exists")]
    AlreadyExists {
        /// What collided.
        what: &'static str,
    },
    /// The request itself is malformed (bad stage graph, empty stage list, bad URL).
    #[error("invalid request: {0}")]
    Invalid(String),
    /// A submission would take the tenant's unfinished stage runs over its cap.
    #[error(
        "backlog full: the tenant has {backlog} unfinished stage runs and this job adds {adding} (cap {cap})"
    )]
    BacklogFull {
        /// Unfinished stage runs now.
        backlog: u64,
        /// Runs the job would add.
        adding: u64,
        /// The cap.
        cap: u64,
    },
    /// A row holds a value this code cannot read (unknown state, malformed JSON).
    #[error("corrupt row: {0}")]
    CorruptRow(String),
    /// The database failed or could not be reached.
    #[error("database error")]
    Database(#[from] sqlx::Error),
    /// Applying migrations failed.
    #[error("migration failed")]
    Migrate(#[from] sqlx::migrate::MigrateError),
}

/// The few classes of error a caller acts on (house style E2); map these, not the variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueueErrorKind {
    /// The caller's lease is gone or its job was cancelled: drop the work, do not retry.
    Fenced,
    /// The row does not exist for this tenant (HTTP 404).
    NotFound,
    /// The row's state or a unique value forbids the operation (HTTP 409).
    Conflict,
    /// The request is malformed (HTTP 400).
    InvalidInput,
    /// The tenant's backlog is at its cap; retrying later may succeed (HTTP 429).
    Busy,
    /// The database failed; retrying later may succeed (HTTP 503).
    Unavailable,
    /// Stored data is unreadable or migrations failed: a bug or a broken deployment (HTTP 500).
    Internal,
}

impl QueueError {
    /// Returns the class of this error.
    #[must_use]
    pub fn kind(&self) -> QueueErrorKind {
        match self {
            Self::LeaseLost { .. } | Self::Cancelled { .. } => QueueErrorKind::Fenced,
            Self::NotFound { .. } => QueueErrorKind::NotFound,
            Self::InvalidTransition { .. } | Self::AlreadyExists { .. } => QueueErrorKind::Conflict,
            Self::Invalid(_) => QueueErrorKind::InvalidInput,
            Self::BacklogFull { .. } => QueueErrorKind::Busy,
            Self::Database(_) => QueueErrorKind::Unavailable,
            Self::CorruptRow(_) | Self::Migrate(_) => QueueErrorKind::Internal,
        }
    }

    pub(crate) fn not_found(what: &'static str, id: impl std::fmt::Display) -> Self {
        Self::NotFound {
            what,
            id: id.to_string(),
        }
    }
}
