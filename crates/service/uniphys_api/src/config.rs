//! What the API enforces and what each submission runs. Built by the binary (libraries never
//! read the environment).

use std::path::PathBuf;
use std::time::Duration;

use uniphys_archive::ArchiveLimits;
use uniphys_queue::JobSpec;

/// Default cap on one upload: 512 MiB.
pub const DEFAULT_MAX_UPLOAD_BYTES: u64 = 512 * 1024 * 1024;

/// Limits and defaults of the HTTP API.
#[derive(Clone, Debug)]
pub struct ApiConfig {
    /// Largest upload accepted; a larger body is answered 413 and nothing is stored.
    pub max_upload_bytes: u64,
    /// An upload whose next bytes take longer than this to arrive is answered 408 and
    /// nothing is stored (a client that stalls after its headers).
    pub body_read_timeout: Duration,
    /// Unfinished stage runs (blocked, ready, running) a tenant may have before submissions are
    /// answered 429.
    pub max_backlog_per_tenant: u64,
    /// The `Retry-After` of a 429, in seconds.
    pub backlog_retry_after_secs: u64,
    /// The stage graph each submission gets (its priority is replaced by the request's).
    pub job_spec: JobSpec,
    /// Most items in one batch manifest.
    pub max_batch_items: usize,
    /// Where uploads are spooled while their digest is computed; `None`: the system temp dir.
    pub upload_tmp_dir: Option<PathBuf>,
    /// Object-store prefixes a tenant may submit by key (`POST /v1/assets/by-url`); `{tenant}`
    /// is replaced by the tenant's number, so one tenant cannot submit another's objects.
    pub url_prefixes: Vec<String>,
    /// The window over which `GET /v1/stats` counts throughput and failures.
    pub stats_window: Duration,
    /// How old the dashboard's statistics (`GET /v1/overview`) may be before a request
    /// recomputes them; many viewers then cost one query per interval.
    pub board_refresh: Duration,
    /// How often the dashboard's history takes a sample.
    pub history_interval: Duration,
    /// Samples kept (720 at 5 s: one hour).
    pub history_len: usize,
    /// How old a batch's statistics may be before a request recomputes them.
    pub batch_stats_refresh: Duration,
    /// What an archive (a multi-file asset) may hold; one over them is answered 422.
    pub archive_limits: ArchiveLimits,
}

impl ApiConfig {
    /// Defaults around `job_spec`: 512 MiB uploads that may pause 30 s between bytes, a
    /// backlog of 10,000 stage runs per tenant, batches of 1,000 items, keys under
    /// `incoming/t{tenant}/` and `sources/t{tenant}/`, archives within [`ArchiveLimits`]'
    /// defaults.
    #[must_use]
    pub fn new(job_spec: JobSpec) -> Self {
        Self {
            max_upload_bytes: DEFAULT_MAX_UPLOAD_BYTES,
            body_read_timeout: Duration::from_secs(30),
            max_backlog_per_tenant: 10_000,
            backlog_retry_after_secs: 30,
            job_spec,
            max_batch_items: 1_000,
            upload_tmp_dir: None,
            url_prefixes: vec!["incoming/t{tenant}/".into(), "sources/t{tenant}/".into()],
            stats_window: Duration::from_secs(300),
            board_refresh: Duration::from_secs(1),
            history_interval: Duration::from_secs(5),
            history_len: 720,
            batch_stats_refresh: Duration::from_secs(5),
            archive_limits: ArchiveLimits::default(),
        }
    }

    /// Sets the upload cap.
    #[must_use]
    pub fn with_max_upload_bytes(mut self, bytes: u64) -> Self {
        self.max_upload_bytes = bytes;
        self
    }

    /// Sets how long an upload may pause between its bytes.
    #[must_use]
    pub fn with_body_read_timeout(mut self, timeout: Duration) -> Self {
        self.body_read_timeout = timeout;
        self
    }

    /// Sets the per-tenant backlog cap.
    #[must_use]
    pub fn with_max_backlog_per_tenant(mut self, runs: u64) -> Self {
        self.max_backlog_per_tenant = runs;
        self
    }

    /// Sets the spool directory of uploads.
    #[must_use]
    pub fn with_upload_tmp_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.upload_tmp_dir = Some(dir.into());
        self
    }
}
