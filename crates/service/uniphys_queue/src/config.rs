//! How to open a store. Libraries never read the environment: the binaries build this.

use std::time::Duration;

use crate::RetryPolicy;

/// Where the queue state lives and how failures are retried.
#[derive(Clone, Debug)]
pub struct StoreConfig {
    /// `postgres://user@host/db` or `sqlite:path/to/queue.db` (embedded mode).
    pub url: String,
    /// Postgres only: the schema holding the tables (sets `search_path`); `None` uses the
    /// role's default (`public`).
    pub schema: Option<String>,
    /// Pool size (SQLite: readers; it always has exactly one writer connection).
    pub max_connections: u32,
    /// How long an operation waits for a free connection before failing.
    pub acquire_timeout: Duration,
    /// Backoff between attempts of a failed stage run.
    pub retry: RetryPolicy,
}

impl StoreConfig {
    /// A config for `url` with default pool and retry settings.
    #[must_use]
    pub fn new(url: impl Into<String>) -> Self {
        Self {
            url: url.into(),
            schema: None,
            max_connections: 10,
            acquire_timeout: Duration::from_secs(30),
            retry: RetryPolicy::default(),
        }
    }

    /// Sets the Postgres schema.
    #[must_use]
    pub fn with_schema(mut self, schema: impl Into<String>) -> Self {
        self.schema = Some(schema.into());
        self
    }

    /// Sets the retry policy.
    #[must_use]
    pub fn with_retry(mut self, retry: RetryPolicy) -> Self {
        self.retry = retry;
        self
    }

    /// Sets the pool size.
    #[must_use]
    pub fn with_max_connections(mut self, max_connections: u32) -> Self {
        self.max_connections = max_connections;
        self
    }
}
