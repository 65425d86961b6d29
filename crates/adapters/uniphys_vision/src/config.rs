use std::time::Duration;

use uniphys_http::RetryPolicy;

use crate::{VisionError, VisionResult};

/// Settings shared by [`crate::SamClient`] and [`crate::PartFieldClient`].
#[derive(Debug, Clone, PartialEq)]
pub struct ClientConfig {
    /// Service base URL, e.g. `http://sam:8000` (paths are appended).
    pub base_url: String,
    /// Limit on opening the TCP connection.
    pub connect_timeout: Duration,
    /// Limit on one attempt, sending to last byte read. A timed-out attempt is retried.
    pub request_timeout: Duration,
    /// Attempts per request, the first included.
    pub max_attempts: u32,
    /// Wait before the second attempt; doubled for each further one (less up to half of it,
    /// jitter).
    pub initial_backoff: Duration,
    /// Longest wait between attempts; also caps a server's `Retry-After`.
    pub max_backoff: Duration,
    /// Largest response body read, bytes.
    pub max_response_bytes: u64,
}

impl Default for ClientConfig {
    fn default() -> Self {
        Self {
            base_url: "http://127.0.0.1:8000".to_owned(),
            connect_timeout: Duration::from_secs(5),
            request_timeout: Duration::from_secs(120),
            max_attempts: 4,
            initial_backoff: Duration::from_millis(500),
            max_backoff: Duration::from_secs(30),
            max_response_bytes: 256 * 1024 * 1024,
        }
    }
}

impl ClientConfig {
    /// The default settings for a service at `base_url`.
    #[must_use]
    pub fn for_url(base_url: impl Into<String>) -> Self {
        Self {
            base_url: base_url.into(),
            ..Self::default()
        }
    }

    /// Checks the settings.
    ///
    /// # Errors
    /// [`VisionError::InvalidOption`] naming the first bad setting.
    pub fn check(&self, service: &'static str) -> VisionResult<()> {
        let invalid = |name, value: String, expected| {
            Err(VisionError::InvalidOption {
                service,
                name,
                value,
                expected,
            })
        };
        if !self.base_url.starts_with("http://") && !self.base_url.starts_with("https://") {
            return invalid(
                "base_url",
                self.base_url.clone(),
                "an http:// or https:// URL",
            );
        }
        if self.max_attempts == 0 {
            return invalid("max_attempts", "0".to_owned(), "at least 1");
        }
        if self.connect_timeout.is_zero() {
            return invalid("connect_timeout", "0 s".to_owned(), "more than zero");
        }
        if self.request_timeout.is_zero() {
            return invalid("request_timeout", "0 s".to_owned(), "more than zero");
        }
        if self.max_response_bytes == 0 {
            return invalid("max_response_bytes", "0".to_owned(), "at least 1");
        }
        Ok(())
    }

    /// These settings as the shared retry policy (half of each backoff jitter, no deadline
    /// beyond the attempts).
    #[must_use]
    pub fn retry_policy(&self) -> RetryPolicy {
        RetryPolicy::exponential(self.max_attempts, self.initial_backoff, self.max_backoff)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles_is_capped_and_honours_retry_after() {
        let config = ClientConfig {
            initial_backoff: Duration::from_millis(100),
            max_backoff: Duration::from_millis(1000),
            ..ClientConfig::default()
        };
        let policy = config.retry_policy();
        assert_eq!(policy.backoff_ceiling(1), Duration::from_millis(100));
        assert_eq!(policy.backoff_ceiling(3), Duration::from_millis(400));
        assert_eq!(policy.backoff_ceiling(9), Duration::from_millis(1000));
        assert_eq!(
            policy.delay(4, b"k", Some(Duration::from_millis(70))),
            Duration::from_millis(70)
        );
        assert_eq!(
            policy.delay(1, b"k", Some(Duration::from_secs(60))),
            Duration::from_millis(1000)
        );
    }

    #[test]
    fn bad_settings_are_named() {
        let zero = ClientConfig {
            max_attempts: 0,
            ..ClientConfig::default()
        };
        let error = zero.check("sam").unwrap_err().to_string();
        assert!(error.contains("max_attempts"), "{error}");
        let url = ClientConfig::for_url("ftp://x");
        assert!(
            url.check("sam")
                .unwrap_err()
                .to_string()
                .contains("base_url")
        );
        assert!(ClientConfig::default().check("sam").is_ok());
    }
}
