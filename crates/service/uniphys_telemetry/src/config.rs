//! What to log, how, and where traces go.

use std::str::FromStr;

use crate::{TelemetryError, TelemetryResult};

/// How log lines are written to standard error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LogFormat {
    /// Human-readable lines (local runs).
    #[default]
    Text,
    /// One JSON object per line, with the current span and its parents (log collectors).
    Json,
}

impl FromStr for LogFormat {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "text" => Ok(Self::Text),
            "json" => Ok(Self::Json),
            other => Err(format!(
                "unknown log format {other:?}: expected text or json"
            )),
        }
    }
}

/// Telemetry settings of one process (API server or worker).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TelemetryConfig {
    /// Text or JSON log lines.
    pub log_format: LogFormat,
    /// Which spans and events are logged, in `EnvFilter` syntax (`info`,
    /// `uniphys_worker=debug,sqlx=warn`). Exported traces record `info` and above regardless,
    /// so quieter logs keep the request and stage spans.
    pub log_filter: String,
    /// Base URL of an OTLP/HTTP collector (`http://collector:4318`); traces are exported in
    /// protobuf to `<endpoint>/v1/traces`. `None` (the default) exports no traces.
    pub otlp_endpoint: Option<String>,
    /// The `service.name` traces are reported under (`uniphys-api`, `uniphys-worker`).
    pub service_name: String,
}

/// Path of the OTLP/HTTP traces signal under a collector's base URL.
const TRACES_PATH: &str = "/v1/traces";

impl TelemetryConfig {
    /// Text logs at `info`, no trace export, reported as `service_name`.
    #[must_use]
    pub fn new(service_name: impl Into<String>) -> Self {
        Self {
            log_format: LogFormat::Text,
            log_filter: "info".to_owned(),
            otlp_endpoint: None,
            service_name: service_name.into(),
        }
    }

    /// Sets the log format.
    #[must_use]
    pub fn with_log_format(mut self, log_format: LogFormat) -> Self {
        self.log_format = log_format;
        self
    }

    /// Sets the `EnvFilter` directives.
    #[must_use]
    pub fn with_log_filter(mut self, log_filter: impl Into<String>) -> Self {
        self.log_filter = log_filter.into();
        self
    }

    /// Exports traces to the OTLP/HTTP collector at `endpoint`.
    #[must_use]
    pub fn with_otlp_endpoint(mut self, endpoint: impl Into<String>) -> Self {
        self.otlp_endpoint = Some(endpoint.into());
        self
    }

    /// The URL spans are posted to, when export is on: the endpoint with `/v1/traces` appended
    /// unless it ends with it already. Only `http://` is accepted: the exporter's client has
    /// no TLS (the collector runs on the cluster network or as a sidecar).
    pub fn traces_url(&self) -> TelemetryResult<Option<String>> {
        let Some(endpoint) = self.otlp_endpoint.as_deref() else {
            return Ok(None);
        };
        let invalid = |message: &str| TelemetryError::OtlpEndpoint {
            endpoint: endpoint.to_owned(),
            message: message.to_owned(),
        };
        let trimmed = endpoint.trim().trim_end_matches('/');
        let Some(rest) = trimmed.strip_prefix("http://") else {
            return Err(invalid("expected an http:// URL (no TLS support)"));
        };
        if rest.is_empty() || rest.starts_with('/') {
            return Err(invalid("missing host"));
        }
        let url = if trimmed.ends_with(TRACES_PATH) {
            trimmed.to_owned()
        } else {
            format!("{trimmed}{TRACES_PATH}")
        };
        url.parse::<http::Uri>()
            .map_err(|e| invalid(&e.to_string()))?;
        Ok(Some(url))
    }
}

impl Default for TelemetryConfig {
    fn default() -> Self {
        Self::new("uniphys")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn traces_url_appends_the_signal_path_once() {
        let url = |e: &str| {
            TelemetryConfig::default()
                .with_otlp_endpoint(e)
                .traces_url()
                .expect("valid endpoint")
        };
        assert_eq!(
            url("http://collector:4318"),
            Some("http://collector:4318/v1/traces".to_owned())
        );
        assert_eq!(
            url("http://collector:4318/"),
            Some("http://collector:4318/v1/traces".to_owned())
        );
        assert_eq!(
            url("http://c:4318/v1/traces"),
            Some("http://c:4318/v1/traces".to_owned())
        );
        assert_eq!(TelemetryConfig::default().traces_url().expect("off"), None);
    }

    #[test]
    fn traces_url_rejects_tls_and_garbage() {
        for bad in [
            "https://collector:4318",
            "collector:4318",
            "http://",
            "http:// x",
        ] {
            let result = TelemetryConfig::default()
                .with_otlp_endpoint(bad)
                .traces_url();
            assert!(
                matches!(result, Err(TelemetryError::OtlpEndpoint { .. })),
                "{bad}: {result:?}"
            );
        }
    }

    #[test]
    fn log_format_parses_case_insensitively() {
        assert_eq!("JSON".parse::<LogFormat>(), Ok(LogFormat::Json));
        assert_eq!("text".parse::<LogFormat>(), Ok(LogFormat::Text));
        assert!("yaml".parse::<LogFormat>().is_err());
    }
}
