//! The service's configuration keys: one flag per key, each also read from an environment variable
//! (`UNIPHYS_*`), the same names in `docker-compose.yml` and `deploy/`. With nothing set, the
//! service is embedded: SQLite and objects under `./uniphys-data`, in-process hints.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, bail};
use uniphys_queue::{RetryPolicy, StoreConfig};

/// Where state, objects and hints live (every server command).
#[derive(Debug, Clone, clap::Args)]
pub struct ServiceArgs {
    /// Directory for embedded state (SQLite queue, local objects, the local API key).
    #[arg(long, env = "UNIPHYS_DATA_DIR", default_value = "uniphys-data")]
    pub data_dir: PathBuf,
    /// Queue database: `postgres://user:pass@host/db` or `sqlite:path`
    /// (default: `sqlite:<data-dir>/queue.db`).
    #[arg(long, env = "UNIPHYS_DATABASE_URL")]
    pub database_url: Option<String>,
    /// How long an operation waits for a database connection before failing (the API then
    /// answers 503 with Retry-After).
    #[arg(
        long,
        env = "UNIPHYS_DATABASE_ACQUIRE_TIMEOUT_SECS",
        default_value_t = 5
    )]
    pub database_acquire_timeout_secs: u64,
    /// Postgres schema holding the queue tables (default: the role's search path).
    #[arg(long, env = "UNIPHYS_DATABASE_SCHEMA")]
    pub database_schema: Option<String>,
    /// Connections in the database pool.
    #[arg(long, env = "UNIPHYS_DATABASE_POOL", default_value_t = 10)]
    pub database_pool: u32,
    /// Object store: a directory, `file:///abs/dir`, `memory://` or `s3://bucket[/prefix]`
    /// (default: `<data-dir>/objects`). S3 settings come from `AWS_ENDPOINT_URL`, `AWS_REGION`, `AWS_ACCESS_KEY_ID`, `AWS_SECRET_ACCESS_KEY`, `AWS_ALLOW_HTTP`.
    #[arg(long, env = "UNIPHYS_STORAGE_URL")]
    pub storage_url: Option<String>,
    /// Redis for wake-up hints, rate limits and progress, e.g. `redis://127.0.0.1:6379/`
    /// (default: in-process hints, enough for one process).
    #[arg(long, env = "UNIPHYS_REDIS_URL")]
    pub redis_url: Option<String>,
    /// Prefix of every Redis key this deployment uses.
    #[arg(long, env = "UNIPHYS_REDIS_PREFIX", default_value = "uniphys")]
    pub redis_prefix: String,
    /// Backoff after a stage's first failed attempt, in milliseconds (doubles per attempt).
    #[arg(long, env = "UNIPHYS_RETRY_BASE_MS", default_value_t = 5000)]
    pub retry_base_ms: u64,
    /// Cap on the backoff between attempts, in seconds.
    #[arg(long, env = "UNIPHYS_RETRY_MAX_SECS", default_value_t = 600)]
    pub retry_max_secs: u64,
    /// Log format: `text` or `json`.
    #[arg(long, env = "UNIPHYS_LOG_FORMAT", default_value = "text")]
    pub log_format: String,
    /// Log filter (tracing `EnvFilter` syntax).
    #[arg(long, env = "UNIPHYS_LOG", default_value = "info")]
    pub log: String,
    /// OTLP/HTTP endpoint for traces, e.g. `http://collector:4318` (default: traces off).
    #[arg(long, env = "UNIPHYS_OTLP_ENDPOINT")]
    pub otlp_endpoint: Option<String>,
}

impl ServiceArgs {
    /// The queue store's configuration.
    pub fn store_config(&self) -> anyhow::Result<StoreConfig> {
        let url = match &self.database_url {
            Some(url) => url.clone(),
            None => {
                std::fs::create_dir_all(&self.data_dir).with_context(|| {
                    format!(
                        "cannot create the data directory {}",
                        self.data_dir.display()
                    )
                })?;
                format!("sqlite:{}", self.data_dir.join("queue.db").display())
            }
        };
        let retry = RetryPolicy {
            base_delay: Duration::from_millis(self.retry_base_ms),
            max_delay: Duration::from_secs(self.retry_max_secs),
        };
        let mut config = StoreConfig::new(url)
            .with_max_connections(self.database_pool)
            .with_retry(retry);
        config.acquire_timeout = Duration::from_secs(self.database_acquire_timeout_secs.max(1));
        if let Some(schema) = &self.database_schema {
            config = config.with_schema(schema.clone());
        }
        Ok(config)
    }

    /// The object store's URL.
    #[must_use]
    pub fn storage_url(&self) -> String {
        self.storage_url
            .clone()
            .unwrap_or_else(|| self.data_dir.join("objects").display().to_string())
    }

    /// Where `serve` keeps the local tenant's API key.
    #[must_use]
    pub fn api_key_file(&self) -> PathBuf {
        self.data_dir.join("api-key")
    }
}

/// Parses `ingest=2,convert=1` (a bare name means one slot).
pub fn parse_stage_slots(text: &str) -> anyhow::Result<Vec<(String, usize)>> {
    let mut slots = Vec::new();
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (name, count) = match item.split_once('=') {
            Some((name, count)) => {
                let count: usize = count.trim().parse().with_context(|| {
                    format!("stage {name}: concurrency {count:?} is not a whole number")
                })?;
                (name.trim(), count)
            }
            None => (item, 1),
        };
        if name.is_empty() || count == 0 {
            bail!("stage slots {item:?}: write name=count with count >= 1");
        }
        slots.push((name.to_owned(), count));
    }
    if slots.is_empty() {
        bail!("no stages given; write e.g. ingest=2,convert=1");
    }
    Ok(slots)
}

/// Whole seconds as a duration, refusing zero.
pub fn secs(value: u64, what: &str) -> anyhow::Result<Duration> {
    if value == 0 {
        bail!("{what} must be at least 1 s");
    }
    Ok(Duration::from_secs(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_slots_parse_with_defaults_and_refuse_nonsense() {
        assert_eq!(
            parse_stage_slots("ingest=2, convert").expect("valid"),
            [("ingest".to_owned(), 2), ("convert".to_owned(), 1)]
        );
        for bad in ["", "ingest=0", "ingest=x", "=3"] {
            assert!(parse_stage_slots(bad).is_err(), "{bad}");
        }
    }
}
