//! Opening what every server command needs, from [`ServiceArgs`]: telemetry, the queue store
//! (migrated), the object store and the hints.

use anyhow::Context;
use uniphys_hints::Hints;
use uniphys_queue::QueueStore;
use uniphys_storage::{ArtifactStore, StorageOptions};
use uniphys_telemetry::{LogFormat, TelemetryConfig, TelemetryGuard};

use super::config::ServiceArgs;

/// The opened parts of the service.
pub struct Opened {
    pub store: QueueStore,
    pub artifacts: ArtifactStore,
    pub hints: Hints,
}

/// Installs logging and (if configured) trace export for the process named `service`.
pub fn telemetry(args: &ServiceArgs, service: &str) -> anyhow::Result<TelemetryGuard> {
    let format: LogFormat = args
        .log_format
        .parse()
        .map_err(|e| anyhow::anyhow!("UNIPHYS_LOG_FORMAT: {e}"))?;
    let mut config = TelemetryConfig::new(service)
        .with_log_format(format)
        .with_log_filter(args.log.clone());
    if let Some(endpoint) = &args.otlp_endpoint {
        config = config.with_otlp_endpoint(endpoint.clone());
    }
    uniphys_telemetry::init(&config).context("cannot start logging and tracing")
}

/// Opens the store (applying migrations when `migrate`), the object store and the hints.
pub async fn open(args: &ServiceArgs, migrate: bool) -> anyhow::Result<Opened> {
    let config = args.store_config()?;
    let store = QueueStore::connect(&config)
        .await
        .with_context(|| format!("cannot reach the queue database {}", redact(&config.url)))?;
    if migrate {
        store
            .migrate()
            .await
            .context("cannot apply the queue migrations")?;
    }
    let options =
        StorageOptions::from_env_map(std::env::vars()).context("object-store settings (AWS_*)")?;
    let storage_url = args.storage_url();
    let artifacts = ArtifactStore::from_url(&storage_url, &options)
        .with_context(|| format!("cannot open the object store {storage_url}"))?;
    let hints = match &args.redis_url {
        Some(url) => Hints::redis(url, &args.redis_prefix)
            .with_context(|| format!("invalid Redis URL {}", redact(url)))?,
        None => Hints::local(),
    };
    Ok(Opened {
        store,
        artifacts,
        hints,
    })
}

/// A URL with its password replaced by `***`, for messages.
#[must_use]
pub fn redact(url: &str) -> String {
    match (url.find("://"), url.rfind('@')) {
        (Some(scheme), Some(at)) if at > scheme => {
            let userinfo = &url[scheme + 3..at];
            match userinfo.split_once(':') {
                Some((user, _)) => format!("{}{user}:***{}", &url[..scheme + 3], &url[at..]),
                None => url.to_owned(),
            }
        }
        _ => url.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn passwords_are_redacted() {
        assert_eq!(
            super::redact("postgres://u:secret@h:5432/db"),
            "postgres://u:***@h:5432/db"
        );
        assert_eq!(super::redact("sqlite:data/q.db"), "sqlite:data/q.db");
        assert_eq!(super::redact("redis://h:6379/"), "redis://h:6379/");
    }
}
