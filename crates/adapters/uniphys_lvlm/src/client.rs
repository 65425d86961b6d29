use std::sync::Arc;
use std::time::Duration;

use uniphys_http::{
    Class, Failure as HttpFailure, FailureKind, HttpClient, HttpConfig, HttpError, RetryPolicy,
    Step, status_class,
};

use crate::ledger::estimate_cost_usd;
use crate::response::{Failure, parse_inner, server_message, usage_of};
use crate::{
    API_KEY_VARIABLE, AnswerCache, CachedAnswer, ChatRequest, ChatResponse, CostLedger, LvlmConfig,
    LvlmError, LvlmResult, Permits, RateLimiter, Usage, estimate_prompt_tokens,
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
        failure: HttpFailure,
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
    http: HttpClient,
    policy: RetryPolicy,
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
        let http = HttpClient::new(HttpConfig {
            connect_timeout: config.connect_timeout(),
            attempt_timeout: config.request_timeout(),
            max_response_bytes: MAX_RESPONSE_BYTES,
            user_agent: "uniphys-lvlm".to_owned(),
            max_idle_per_host: config.max_concurrency.max(3),
        })
        .map_err(|error| LvlmError::InvalidConfig {
            name: "connect_timeout_secs / request_timeout_secs",
            value: error.to_string(),
            expected: "settings the HTTP client accepts",
        })?;
        let policy = RetryPolicy::exponential(
            config.max_attempts,
            config.backoff_initial(),
            config.backoff_max(),
        );
        let permits = Permits::new(config.max_concurrency);
        Ok(Self {
            config,
            http,
            policy,
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
    /// rate-limiter token, then `POST {base_url}/chat/completions`. The shared retry policy
    /// (`uniphys_http`): 408, 425, 429, 500, 502, 503, 504 (a `Retry-After` on 429/503
    /// honoured, capped at `backoff_max_secs`), timeouts, connection errors and truncated
    /// bodies, and here also malformed bodies, are retried with jittered exponential backoff up
    /// to `max_attempts`; other statuses fail at once. Usage of every attempt that reported one
    /// is charged; an answer without usage is charged an estimate (marked `estimated`).
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
        let url = format!(
            "{}{COMPLETIONS_PATH}",
            self.config.base_url.trim_end_matches('/')
        );
        let mut cost_usd = 0.0;
        let mut attempts = 0;
        let response = self.policy.run(
            body.digest.as_bytes(),
            |attempt| {
                attempts = attempt.number;
                let _reservation = match ledger.reserve(purpose, estimated_usd) {
                    Ok(reservation) => reservation,
                    Err(error) => return Step::Stop(error),
                };
                let outcome = {
                    let _permit = self.permits.acquire();
                    if let Err(error) = self.limiter.acquire() {
                        ledger.record_failed_attempt(purpose, None, false);
                        return Step::Stop(error);
                    }
                    self.attempt(&url, &body.json, purpose, attempt.time_left)
                };
                // Charge while the reservation is held, so the budget never misses this cost.
                match outcome {
                    Attempt::Answer(response) => {
                        let usage = response
                            .usage
                            .unwrap_or_else(|| estimated_usage(request, &response.text));
                        let cost = self.cost(&usage);
                        cost_usd += cost;
                        ledger.record_answer(purpose, &usage, cost);
                        Step::Done(response)
                    }
                    Attempt::Retry { failure, usage } => {
                        let charged = usage.map(|u| (u, self.cost(&u)));
                        cost_usd += charged.map_or(0.0, |(_, c)| c);
                        ledger.record_failed_attempt(
                            purpose,
                            charged.as_ref().map(|(u, c)| (u, *c)),
                            !attempt.is_last,
                        );
                        Step::Retry(failure)
                    }
                    Attempt::Fail { error, usage } => {
                        let charged = usage.map(|u| (u, self.cost(&u)));
                        ledger.record_failed_attempt(
                            purpose,
                            charged.as_ref().map(|(u, c)| (u, *c)),
                            false,
                        );
                        Step::Stop(error)
                    }
                }
            },
            |_| {},
            |error| gave_up(purpose, error),
        )?;
        Ok(self.answer(response, request, body.digest, cost_usd, attempts))
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

    /// One HTTP attempt, judged: an answer, a transient failure (retried), or an error.
    fn attempt(
        &self,
        url: &str,
        body_json: &str,
        purpose: &str,
        time_left: Option<Duration>,
    ) -> Attempt {
        let mut builder = self
            .http
            .inner()
            .post(url)
            .header("Content-Type", "application/json")
            .body(body_json.to_owned());
        if let Some(key) = &self.config.api_key {
            builder = builder.header("Authorization", format!("Bearer {key}"));
        }
        let reply = match self.http.exchange(builder, time_left) {
            Ok(reply) => reply,
            Err(failure) => return self.transport_failure(failure),
        };
        let (status, body) = (reply.status, reply.body.as_str());
        match status_class(status) {
            None => match parse_inner(body) {
                Ok(response) => Attempt::Answer(response),
                Err(Failure::Malformed(what)) => Attempt::Retry {
                    failure: HttpFailure::body(format!("malformed response: {what}")).transient(),
                    usage: usage_of(body),
                },
                Err(Failure::Refused(message)) => Attempt::Fail {
                    error: LvlmError::ModelRefused {
                        purpose: purpose.to_owned(),
                        message,
                    },
                    usage: usage_of(body),
                },
            },
            Some(Class::Transient) => Attempt::Retry {
                failure: HttpFailure::status(status, server_message(body), reply.retry_after),
                usage: None,
            },
            Some(Class::Permanent) if matches!(status, 401 | 403) => Attempt::Fail {
                error: LvlmError::Unauthorized {
                    status,
                    message: server_message(body),
                    key_variable: API_KEY_VARIABLE,
                },
                usage: None,
            },
            Some(Class::Permanent) => Attempt::Fail {
                error: LvlmError::Refused {
                    purpose: purpose.to_owned(),
                    status,
                    message: server_message(body),
                },
                usage: None,
            },
        }
    }

    /// A failure before an answer was read whole: transient ones (connection, timeout,
    /// interrupted) are retried; a bad URL and an oversized body are not.
    fn transport_failure(&self, failure: HttpFailure) -> Attempt {
        let error = match failure.kind {
            _ if failure.is_transient() => {
                return Attempt::Retry {
                    failure,
                    usage: None,
                };
            }
            FailureKind::Unsendable => LvlmError::InvalidConfig {
                name: "base_url",
                value: self.config.base_url.clone(),
                expected: "a valid http:// URL",
            },
            _ => LvlmError::Malformed {
                what: failure.to_string(),
            },
        };
        Attempt::Fail { error, usage: None }
    }
}

/// The error of a request whose every allowed attempt failed transiently.
fn gave_up(purpose: &str, error: HttpError) -> LvlmError {
    let (attempts, last_failure) = match error {
        HttpError::GaveUp { attempts, last, .. } => (attempts, last.to_string()),
        other => (0, other.to_string()),
    };
    LvlmError::GaveUp {
        purpose: purpose.to_owned(),
        attempts,
        last_failure,
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
