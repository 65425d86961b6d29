use std::time::Duration;

use crate::{LvlmError, LvlmResult};

/// The environment variable callers conventionally read the API key from (the client itself
/// never reads the environment; error messages name this variable).
pub const API_KEY_VARIABLE: &str = "UNIPHYS_LVLM_API_KEY";

/// Prices of a model, used for cost accounting and the budget.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pricing {
    /// USD per million prompt (input) tokens, images included.
    pub input_usd_per_million_tokens: f64,
    /// USD per million completion (output) tokens, reasoning tokens included.
    pub output_usd_per_million_tokens: f64,
}

impl Default for Pricing {
    /// gpt-5 list prices as printed by the reference: 1.25 USD in, 10 USD out per million.
    fn default() -> Self {
        Self {
            input_usd_per_million_tokens: 1.25,
            output_usd_per_million_tokens: 10.0,
        }
    }
}

impl Pricing {
    /// Cost in USD of `prompt_tokens` in and `completion_tokens` out.
    #[must_use]
    pub fn cost_usd(&self, prompt_tokens: u64, completion_tokens: u64) -> f64 {
        (prompt_tokens as f64 * self.input_usd_per_million_tokens
            + completion_tokens as f64 * self.output_usd_per_million_tokens)
            / 1e6
    }
}

/// Settings of an [`LvlmClient`](crate::LvlmClient). Times are in seconds (fractions allowed,
/// so tests can use milliseconds).
#[derive(Clone, PartialEq)]
pub struct LvlmConfig {
    /// Server base URL including the API prefix, e.g. `http://vllm:8000/v1`; the client posts
    /// to `{base_url}/chat/completions`. Plain HTTP only: reach hosted APIs through an
    /// in-cluster gateway. Default `http://127.0.0.1:8000/v1`.
    pub base_url: String,
    /// Model name sent with every request. Default `gpt-5`.
    pub model: String,
    /// Bearer token, if the server wants one. Never logged, hashed or cached.
    pub api_key: Option<String>,
    /// `reasoning_effort` sent when set (`minimal`, `low`, `medium`, `high`). Default `medium`,
    /// as the reference.
    pub reasoning_effort: Option<String>,
    /// `max_completion_tokens` sent when set (reasoning tokens count against it). Default none.
    pub max_completion_tokens: Option<u32>,
    /// Limit on establishing a connection. Default 10 s.
    pub connect_timeout_secs: f64,
    /// Limit on one attempt, sending to last byte read. Default 120 s.
    pub request_timeout_secs: f64,
    /// Attempts per request, the first included. Default 4.
    pub max_attempts: u32,
    /// Wait before the second attempt, doubled for each further one (with jitter). Default 1 s.
    pub backoff_initial_secs: f64,
    /// Longest wait between attempts; also caps a server's `Retry-After` (honoured on 429 and
    /// 503). Default 30 s.
    pub backoff_max_secs: f64,
    /// Most requests in flight from this client at once. Default 8.
    pub max_concurrency: usize,
    /// Prices for cost accounting. Default [`Pricing::default`].
    pub pricing: Pricing,
}

impl std::fmt::Debug for LvlmConfig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LvlmConfig")
            .field("base_url", &self.base_url)
            .field("model", &self.model)
            .field("api_key", &self.api_key.as_ref().map(|_| "<redacted>"))
            .field("reasoning_effort", &self.reasoning_effort)
            .field("max_completion_tokens", &self.max_completion_tokens)
            .field("connect_timeout_secs", &self.connect_timeout_secs)
            .field("request_timeout_secs", &self.request_timeout_secs)
            .field("max_attempts", &self.max_attempts)
            .field("backoff_initial_secs", &self.backoff_initial_secs)
            .field("backoff_max_secs", &self.backoff_max_secs)
            .field("max_concurrency", &self.max_concurrency)
            .field("pricing", &self.pricing)
            .finish()
    }
}

impl Default for LvlmConfig {
    fn default() -> Self {
        Self {
            base_url: "http://127.0.0.1:8000/v1".to_owned(),
            model: "gpt-5".to_owned(),
            api_key: None,
            reasoning_effort: Some("medium".to_owned()),
            max_completion_tokens: None,
            connect_timeout_secs: 10.0,
            request_timeout_secs: 120.0,
            max_attempts: 4,
            backoff_initial_secs: 1.0,
            backoff_max_secs: 30.0,
            max_concurrency: 8,
            pricing: Pricing::default(),
        }
    }
}

impl LvlmConfig {
    /// Checks every value.
    ///
    /// # Errors
    /// [`LvlmError::InvalidConfig`] naming the first bad option.
    pub fn validate(&self) -> LvlmResult<()> {
        let invalid = |name: &'static str, value: String, expected: &'static str| {
            Err(LvlmError::InvalidConfig {
                name,
                value,
                expected,
            })
        };
        if !self.base_url.starts_with("http://") {
            return invalid(
                "base_url",
                self.base_url.clone(),
                "an http:// URL (the LVLM client speaks plain HTTP: use an in-cluster gateway for https APIs)",
            );
        }
        if self.model.trim().is_empty() {
            return invalid("model", self.model.clone(), "a model name");
        }
        if self.max_attempts == 0 {
            return invalid("max_attempts", "0".to_owned(), "at least 1");
        }
        if self.max_concurrency == 0 {
            return invalid("max_concurrency", "0".to_owned(), "at least 1");
        }
        for (name, value) in [
            ("connect_timeout_secs", self.connect_timeout_secs),
            ("request_timeout_secs", self.request_timeout_secs),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return invalid(name, value.to_string(), "a positive number of seconds");
            }
        }
        for (name, value) in [
            ("backoff_initial_secs", self.backoff_initial_secs),
            ("backoff_max_secs", self.backoff_max_secs),
            (
                "pricing.input_usd_per_million_tokens",
                self.pricing.input_usd_per_million_tokens,
            ),
            (
                "pricing.output_usd_per_million_tokens",
                self.pricing.output_usd_per_million_tokens,
            ),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return invalid(name, value.to_string(), "a finite number >= 0");
            }
        }
        if self.max_completion_tokens == Some(0) {
            return invalid(
                "max_completion_tokens",
                "0".to_owned(),
                "at least 1 or unset",
            );
        }
        Ok(())
    }

    /// `connect_timeout_secs` as a duration.
    #[must_use]
    pub fn connect_timeout(&self) -> Duration {
        secs(self.connect_timeout_secs)
    }

    /// `request_timeout_secs` as a duration.
    #[must_use]
    pub fn request_timeout(&self) -> Duration {
        secs(self.request_timeout_secs)
    }

    /// `backoff_initial_secs` as a duration.
    #[must_use]
    pub fn backoff_initial(&self) -> Duration {
        secs(self.backoff_initial_secs)
    }

    /// `backoff_max_secs` as a duration.
    #[must_use]
    pub fn backoff_max(&self) -> Duration {
        secs(self.backoff_max_secs)
    }
}

/// Seconds as a duration; negative or non-finite values become zero, huge ones the maximum.
fn secs(value: f64) -> Duration {
    Duration::try_from_secs_f64(value.max(0.0)).unwrap_or(Duration::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_match_the_documented_values() {
        let config = LvlmConfig::default();
        config.validate().unwrap();
        assert_eq!(config.request_timeout(), Duration::from_secs(120));
        assert_eq!(config.max_attempts, 4);
        assert_eq!(config.max_concurrency, 8);
        assert_eq!(config.backoff_max(), Duration::from_secs(30));
    }

    #[test]
    fn bad_values_are_named() {
        let cases = [
            LvlmConfig {
                max_attempts: 0,
                ..LvlmConfig::default()
            },
            LvlmConfig {
                max_concurrency: 0,
                ..LvlmConfig::default()
            },
            LvlmConfig {
                request_timeout_secs: f64::NAN,
                ..LvlmConfig::default()
            },
            LvlmConfig {
                base_url: "https://api.example.com/v1".to_owned(),
                ..LvlmConfig::default()
            },
        ];
        let names = [
            "max_attempts",
            "max_concurrency",
            "request_timeout_secs",
            "base_url",
        ];
        for (config, name) in cases.iter().zip(names) {
            let message = config.validate().unwrap_err().to_string();
            assert!(message.contains(name), "{message}");
        }
    }

    #[test]
    fn debug_output_hides_the_key() {
        let config = LvlmConfig {
            api_key: Some("sk-secret-123".to_owned()),
            ..LvlmConfig::default()
        };
        let printed = format!("{config:?}");
        assert!(!printed.contains("sk-secret-123"), "{printed}");
        assert!(printed.contains("<redacted>"));
    }

    #[test]
    fn cost_follows_the_prices() {
        let pricing = Pricing {
            input_usd_per_million_tokens: 2.0,
            output_usd_per_million_tokens: 8.0,
        };
        let cost = pricing.cost_usd(500_000, 250_000);
        assert!((cost - 3.0).abs() < 1e-12, "{cost}");
    }
}
