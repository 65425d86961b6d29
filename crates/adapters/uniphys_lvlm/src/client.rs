use std::sync::Arc;
use std::time::Duration;

use ureq::Agent;

use crate::ledger::estimate_cost_usd;
use crate::response::{Failure, parse_inner, server_message, usage_of};
use crate::{
    API_KEY_VARIABLE, AnswerCache, CachedAnswer, ChatRequest, ChatResponse, CostLedger, LvlmConfig,
    LvlmError, LvlmResult, Permits, RateLimiter, Usage, backoff_delay, estimate_prompt_tokens,
};

/// Largest response body the client reads.
const MAX_RESPONSE_BYTES: u64 = 16 * 1024 * 1024;

/// Path appended to the base URL.
const COMPLETIONS_PATH: &str = "/chat/completions";

/// The model's answer to one [`ChatRequest`].
#[derive(Debug, Clone, PartialEq)]
pub struct ChatAnswer {
    /// The answer text.
    pub text: String,
    /// Tokens of the attempt that answered (zero for a cached answer; failed attempts are in
    /// `cost_usd` and the ledger).
    pub usage: Usage,
    /// USD this call cost, failed attempts that reported usage included (zero when cached).
    pub cost_usd: f64,
    /// The model that answered.
    pub model: String,
    /// `finish_reason` (`length` means the answer was cut off).
    pub finish_reason: Option<String>,
    /// Whether the answer came from the cache.
    pub cached: bool,
    /// HTTP attempts made (0 when cached).
    pub attempts: u32,
    /// The request digest (cache key); pass it to [`LvlmClient::forget`] to drop an answer
    /// that failed validation.
    pub digest: String,
    /// Why the answer could not be stored in the cache, if it could not (the answer is still
    /// good, but a retry of the stage would pay for it again).
    pub cache_error: Option<String>,
}

/// What one HTTP attempt came to.
enum Attempt {
    Answer(ChatResponse),
    Retry {
        reason: String,
        retry_after: Option<Duration>,
        usage: Option<Usage>,
    },
    Fail {
        error: LvlmError,
        usage: Option<Usage>,
    },
}

/// Blocking, thread-safe client of an OpenAI-compatible chat-completions server. Share one
/// (in an `Arc`) between all threads: its concurrency limit is per client.
pub struct LvlmClient {
    config: LvlmConfig,
    agent: Agent,
    limiter: Arc<dyn RateLimiter>,
    cache: Arc<dyn AnswerCache>,
    permits: Permits,
}

impl std::fmt::Debug for LvlmClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LvlmClient")
            .field("config", &self.config)
            .field("in_flight", &self.permits.in_use())
            .finish_non_exhaustive()
    }
}

impl LvlmClient {
    /// A client for `config`, taking a `limiter` token before each attempt and keeping answers
    /// in `cache`.
    ///
    /// # Errors
    /// [`LvlmError::InvalidConfig`] from [`LvlmConfig::validate`].
    pub fn new(
        config: LvlmConfig,
        limiter: Arc<dyn RateLimiter>,
        cache: Arc<dyn AnswerCache>,
    ) -> LvlmResult<Self> {
        config.validate()?;
        let idle = config.max_concurrency.max(3);
        let agent = Agent::config_builder()
            .timeout_global(Some(config.request_timeout()))
            .timeout_connect(Some(config.connect_timeout()))
            .http_status_as_error(false)
            .max_idle_connections(idle)
            .max_idle_connections_per_host(idle)
            .user_agent("uniphys-lvlm")
            .build()
            .new_agent();
        let permits = Permits::new(config.max_concurrency);
        Ok(Self {
            config,
            agent,
            limiter,
            cache,
            permits,
        })
    }

    /// The settings.
    #[must_use]
    pub fn config(&self) -> &LvlmConfig {
        &self.config
    }

    /// Requests in flight from this client now.
    #[must_use]
    pub fn in_flight(&self) -> usize {
        self.permits.in_use()
    }

    /// Drops the cached answer of `digest` (one that failed validation), so asking again
    /// reaches the model.
    ///
    /// # Errors
    /// [`LvlmError::Cache`] if the entry exists but cannot be removed.
    pub fn forget(&self, digest: &str) -> LvlmResult<()> {
        self.cache.remove(digest)
    }

    /// Asks the model, charging `ledger`.
    ///
    /// A cached answer for the same body is returned at no cost. Otherwise, for each attempt:
    /// budget check (spent + in flight + this request's estimate), a concurrency permit, a
    /// rate-limiter token, then `POST {base_url}/chat/completions`. 429 (its `Retry-After`
    /// honoured, capped), 408, 409, 5xx, timeouts, connection errors, truncated and malformed
    /// bodies are retried with jittered exponential backoff up to `max_attempts`; other 4xx
    /// fail at once. Usage of every attempt that reported one is charged; an answer without
    /// usage is charged an estimate (marked `estimated`).
    ///
    /// # Errors
    /// [`LvlmError::BudgetExceeded`] (nothing sent for that attempt), [`LvlmError::GaveUp`],
    /// [`LvlmError::Unauthorized`], [`LvlmError::Refused`], [`LvlmError::ModelRefused`],
    /// [`LvlmError::InvalidRequest`], [`LvlmError::RateLimiter`].
    pub fn complete(&self, request: &ChatRequest, ledger: &CostLedger) -> LvlmResult<ChatAnswer> {
        let purpose = request.purpose.as_str();
        let body = request.body(&self.config)?;
        if let Some(hit) = self.cache.get(&body.digest) {
            ledger.record_cache_hit(purpose);
            return Ok(ChatAnswer {
                text: hit.text,
                usage: Usage::default(),
                cost_usd: 0.0,
                model: hit.model,
                finish_reason: hit.finish_reason,
                cached: true,
                attempts: 0,
                digest: body.digest,
                cache_error: None,
            });
        }
        let estimated_usd = estimate_cost_usd(request, &self.config);
        let mut cost_usd = 0.0;
        let mut attempt = 1;
        loop {
            let last = attempt >= self.config.max_attempts;
            let outcome = {
                let _reservation = ledger.reserve(purpose, estimated_usd)?;
                let outcome = {
                    let _permit = self.permits.acquire();
                    if let Err(error) = self.limiter.acquire() {
                        ledger.record_failed_attempt(purpose, None, false);
                        return Err(error);
                    }
                    self.attempt(&body.json, purpose)
                };
                // Charge while the reservation is held, so the budget never misses this cost.
                match &outcome {
                    Attempt::Answer(response) => {
                        let usage = response
                            .usage
                            .unwrap_or_else(|| estimated_usage(request, &response.text));
                        let cost = self.cost(&usage);
                        cost_usd += cost;
                        ledger.record_answer(purpose, &usage, cost);
                    }
                    Attempt::Retry { usage, .. } => {
                        let charged = usage.map(|u| (u, self.cost(&u)));
                        cost_usd += charged.map_or(0.0, |(_, c)| c);
                        ledger.record_failed_attempt(
                            purpose,
                            charged.as_ref().map(|(u, c)| (u, *c)),
                            !last,
                        );
                    }
                    Attempt::Fail { usage, .. } => {
                        let charged = usage.map(|u| (u, self.cost(&u)));
                        ledger.record_failed_attempt(
                            purpose,
                            charged.as_ref().map(|(u, c)| (u, *c)),
                            false,
                        );
                    }
                }
                outcome
            };
            match outcome {
                Attempt::Answer(response) => {
                    return Ok(self.answer(response, request, body.digest, cost_usd, attempt));
                }
                Attempt::Fail { error, .. } => return Err(error),
                Attempt::Retry {
                    reason,
                    retry_after,
                    ..
                } => {
                    if last {
                        return Err(LvlmError::GaveUp {
                            purpose: purpose.to_owned(),
                            attempts: attempt,
                            last_failure: reason,
                        });
                    }
                    std::thread::sleep(backoff_delay(
                        self.config.backoff_initial(),
                        self.config.backoff_max(),
                        attempt,
                        &body.digest,
                        retry_after,
                    ));
                    attempt += 1;
                }
            }
        }
    }

    fn cost(&self, usage: &Usage) -> f64 {
        self.config
            .pricing
            .cost_usd(usage.prompt_tokens, usage.completion_tokens)
    }

    /// The answer of a successful call, stored in the cache.
    fn answer(
        &self,
        response: ChatResponse,
        request: &ChatRequest,
        digest: String,
        cost_usd: f64,
        attempts: u32,
    ) -> ChatAnswer {
        let usage = response
            .usage
            .unwrap_or_else(|| estimated_usage(request, &response.text));
        let cached = CachedAnswer {
            text: response.text,
            usage,
            model: response.model,
            finish_reason: response.finish_reason,
        };
        let cache_error = self
            .cache
            .put(&digest, &cached)
            .err()
            .map(|e| e.to_string());
        ChatAnswer {
            text: cached.text,
            usage,
            cost_usd,
            model: cached.model,
            finish_reason: cached.finish_reason,
            cached: false,
            attempts,
            digest,
            cache_error,
        }
    }

    /// One HTTP attempt.
    fn attempt(&self, body_json: &str, purpose: &str) -> Attempt {
        let url = format!(
            "{}{COMPLETIONS_PATH}",
            self.config.base_url.trim_end_matches('/')
        );
        let mut builder = self
            .agent
            .post(&url)
            .header("Content-Type", "application/json");
        if let Some(key) = &self.config.api_key {
            builder = builder.header("Authorization", format!("Bearer {key}"));
        }
        let mut response = match builder.send(body_json) {
            Ok(response) => response,
            Err(error) => return self.transport_failure(&error),
        };
        let status = response.status().as_u16();
        let retry_after = retry_after(response.headers());
        let body = match response
            .body_mut()
            .with_config()
            .limit(MAX_RESPONSE_BYTES)
            .read_to_string()
        {
            Ok(body) => body,
            Err(error) => {
                let failure = self.transport_failure(&error);
                return match failure {
                    Attempt::Retry { reason, .. } => Attempt::Retry {
                        reason: format!("HTTP {status}, body unreadable: {reason}"),
                        retry_after,
                        usage: None,
                    },
                    other => other,
                };
            }
        };
        match status {
            200..=299 => match parse_inner(&body) {
                Ok(response) => Attempt::Answer(response),
                Err(Failure::Malformed(what)) => Attempt::Retry {
                    reason: format!("malformed response: {what}"),
                    retry_after: None,
                    usage: usage_of(&body),
                },
                Err(Failure::Refused(message)) => Attempt::Fail {
                    error: LvlmError::ModelRefused {
                        purpose: purpose.to_owned(),
                        message,
                    },
                    usage: usage_of(&body),
                },
            },
            408 | 409 | 429 | 500..=599 => Attempt::Retry {
                reason: format!("HTTP {status}: {}", server_message(&body)),
                retry_after,
                usage: None,
            },
            401 | 403 => Attempt::Fail {
                error: LvlmError::Unauthorized {
                    status,
                    message: server_message(&body),
                    key_variable: API_KEY_VARIABLE,
                },
                usage: None,
            },
            _ => Attempt::Fail {
                error: LvlmError::Refused {
                    purpose: purpose.to_owned(),
                    status,
                    message: server_message(&body),
                },
                usage: None,
            },
        }
    }

    fn transport_failure(&self, error: &ureq::Error) -> Attempt {
        let reason = match error {
            ureq::Error::Timeout(which) => format!(
                "timed out ({which}) after request_timeout_secs = {} s",
                self.config.request_timeout_secs
            ),
            ureq::Error::Io(io) if io.kind() == std::io::ErrorKind::TimedOut => format!(
                "timed out after request_timeout_secs = {} s",
                self.config.request_timeout_secs
            ),
            ureq::Error::BadUri(uri) => {
                return Attempt::Fail {
                    error: LvlmError::InvalidConfig {
                        name: "base_url",
                        value: uri.clone(),
                        expected: "a valid http:// URL",
                    },
                    usage: None,
                };
            }
            ureq::Error::BodyExceedsLimit(limit) => {
                format!("the response body exceeds {limit} bytes")
            }
            other => format!("cannot reach {}: {other}", self.config.base_url),
        };
        Attempt::Retry {
            reason,
            retry_after: None,
            usage: None,
        }
    }
}

/// Usage estimated when the server reported none: the request's prompt estimate, and one
/// token per 4 characters of the answer.
fn estimated_usage(request: &ChatRequest, text: &str) -> Usage {
    Usage {
        prompt_tokens: estimate_prompt_tokens(request),
        completion_tokens: (text.chars().count() as u64).div_ceil(4),
        reasoning_tokens: None,
        estimated: true,
    }
}

/// The server's requested wait: `retry-after-ms` (milliseconds) or `retry-after` (seconds;
/// HTTP dates are ignored).
fn retry_after(headers: &ureq::http::HeaderMap) -> Option<Duration> {
    let number = |name: &str| {
        headers
            .get(name)
            .and_then(|v| v.to_str().ok())
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|v| v.is_finite() && *v >= 0.0)
    };
    number("retry-after-ms")
        .map(|ms| ms / 1000.0)
        .or_else(|| number("retry-after"))
        .and_then(|secs| Duration::try_from_secs_f64(secs).ok())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{NoCache, NoRateLimit};

    fn assert_send_sync<T: Send + Sync>() {}

    #[test]
    fn the_client_is_shareable_between_threads() {
        assert_send_sync::<LvlmClient>();
        assert_send_sync::<CostLedger>();
    }

    #[test]
    fn retry_after_reads_seconds_and_milliseconds() {
        let mut headers = ureq::http::HeaderMap::new();
        assert_eq!(retry_after(&headers), None);
        headers.insert("retry-after", "2".parse().unwrap());
        assert_eq!(retry_after(&headers), Some(Duration::from_secs(2)));
        headers.insert("retry-after-ms", "250".parse().unwrap());
        assert_eq!(retry_after(&headers), Some(Duration::from_millis(250)));
        let mut dated = ureq::http::HeaderMap::new();
        dated.insert(
            "retry-after",
            "Wed, 21 Oct 2015 07:28:00 GMT".parse().unwrap(),
        );
        assert_eq!(retry_after(&dated), None);
    }

    #[test]
    fn an_invalid_config_is_refused_at_construction() {
        let config = LvlmConfig {
            max_attempts: 0,
            ..LvlmConfig::default()
        };
        let error = LvlmClient::new(config, Arc::new(NoRateLimit), Arc::new(NoCache)).unwrap_err();
        assert!(error.to_string().contains("max_attempts"), "{error}");
    }

    #[test]
    fn an_answer_without_usage_is_charged_an_estimate() {
        let request = ChatRequest::new("p", "12345678", "");
        let usage = estimated_usage(&request, "abcdefghi");
        assert_eq!((usage.prompt_tokens, usage.completion_tokens), (2, 3));
        assert!(usage.estimated);
    }
}
