//! One retrying JSON request over `ureq`, shared by both clients.

use std::time::Duration;

use serde::Serialize;
use serde::de::DeserializeOwned;
use ureq::Agent;

use crate::{ClientConfig, VisionError, VisionResult};

/// A configured HTTP client for one service.
pub(crate) struct Transport {
    config: ClientConfig,
    agent: Agent,
    service: &'static str,
}

impl std::fmt::Debug for Transport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Transport")
            .field("service", &self.service)
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

/// What one attempt came to.
enum Outcome {
    Answer(String),
    Retry {
        reason: String,
        retry_after: Option<Duration>,
    },
    Fail(VisionError),
}

impl Transport {
    pub(crate) fn new(config: ClientConfig, service: &'static str) -> VisionResult<Self> {
        config.check(service)?;
        let agent = Agent::config_builder()
            .timeout_connect(Some(config.connect_timeout))
            .timeout_global(Some(config.request_timeout))
            .http_status_as_error(false)
            .build()
            .new_agent();
        Ok(Self {
            config,
            agent,
            service,
        })
    }

    pub(crate) fn config(&self) -> &ClientConfig {
        &self.config
    }

    fn url(&self, path: &str) -> String {
        format!("{}{path}", self.config.base_url.trim_end_matches('/'))
    }

    /// `GET path` once; Ok if the service answers 2xx.
    pub(crate) fn health(&self, path: &'static str) -> VisionResult<()> {
        match self.attempt(path, None) {
            Outcome::Answer(_) => Ok(()),
            Outcome::Retry { reason, .. } => Err(VisionError::Unhealthy {
                service: self.service,
                base_url: self.config.base_url.clone(),
                timeout: self.config.request_timeout,
                reason,
            }),
            Outcome::Fail(error) => Err(error),
        }
    }

    /// `POST path` with `request` as JSON, retrying connection errors, timeouts, 429, 5xx and
    /// truncated or syntactically malformed bodies; an answer that is JSON but does not fit
    /// `T` is a contract violation and is not retried.
    pub(crate) fn post<Q: Serialize, T: DeserializeOwned>(
        &self,
        path: &'static str,
        request: &Q,
    ) -> VisionResult<T> {
        let body = serde_json::to_vec(request).map_err(|error| VisionError::InvalidInput {
            service: self.service,
            reason: format!("the request cannot be serialised: {error}"),
        })?;
        let mut attempt = 1;
        loop {
            let (reason, retry_after) = match self.attempt(path, Some(&body)) {
                Outcome::Answer(text) => match serde_json::from_str::<serde_json::Value>(&text) {
                    Ok(value) => {
                        return serde_json::from_value(value).map_err(|error| {
                            VisionError::InvalidAnswer {
                                service: self.service,
                                path,
                                reason: error.to_string(),
                            }
                        });
                    }
                    Err(error) => (
                        format!("malformed JSON answer ({error}): {}", excerpt(&text)),
                        None,
                    ),
                },
                Outcome::Retry {
                    reason,
                    retry_after,
                } => (reason, retry_after),
                Outcome::Fail(error) => return Err(error),
            };
            if attempt >= self.config.max_attempts {
                return Err(VisionError::GaveUp {
                    service: self.service,
                    path,
                    base_url: self.config.base_url.clone(),
                    attempts: attempt,
                    reason,
                });
            }
            std::thread::sleep(self.config.backoff(attempt, retry_after));
            attempt += 1;
        }
    }

    fn attempt(&self, path: &'static str, body: Option<&[u8]>) -> Outcome {
        let url = self.url(path);
        let response = match body {
            Some(body) => self
                .agent
                .post(&url)
                .header("content-type", "application/json")
                .send(body),
            None => self.agent.get(&url).call(),
        };
        let mut response = match response {
            Ok(response) => response,
            Err(error) => return self.transport_outcome(&url, error),
        };
        let status = response.status().as_u16();
        let retry_after = response
            .headers()
            .get("retry-after")
            .and_then(|value| value.to_str().ok())
            .and_then(parse_retry_after);
        let text = match response
            .body_mut()
            .with_config()
            .limit(self.config.max_response_bytes)
            .read_to_string()
        {
            Ok(text) => text,
            Err(error) => return self.transport_outcome(&url, error),
        };
        match status {
            200..=299 => Outcome::Answer(text),
            429 | 503 => Outcome::Retry {
                reason: format!("HTTP {status}: {}", server_message(&text)),
                retry_after,
            },
            500..=599 => Outcome::Retry {
                reason: format!("HTTP {status}: {}", server_message(&text)),
                retry_after: None,
            },
            _ => Outcome::Fail(VisionError::Refused {
                service: self.service,
                path,
                status,
                message: server_message(&text),
            }),
        }
    }

    fn transport_outcome(&self, url: &str, error: ureq::Error) -> Outcome {
        let reason = match &error {
            ureq::Error::Timeout(_) => format!(
                "no complete answer within {:?} ({error})",
                self.config.request_timeout
            ),
            ureq::Error::Io(io) if io.kind() == std::io::ErrorKind::TimedOut => format!(
                "no complete answer within {:?} ({error})",
                self.config.request_timeout
            ),
            ureq::Error::Io(_)
            | ureq::Error::ConnectionFailed
            | ureq::Error::HostNotFound
            | ureq::Error::Protocol(_)
            | ureq::Error::BodyStalled => format!("connection or truncated answer: {error}"),
            _ => {
                return Outcome::Fail(VisionError::Transport {
                    service: self.service,
                    url: url.to_owned(),
                    reason: error.to_string(),
                });
            }
        };
        Outcome::Retry {
            reason,
            retry_after: None,
        }
    }
}

/// `Retry-After` as delay seconds (an HTTP date is ignored: the exponential backoff applies).
fn parse_retry_after(value: &str) -> Option<Duration> {
    let seconds: f64 = value.trim().parse().ok()?;
    (seconds.is_finite() && seconds >= 0.0).then(|| Duration::from_secs_f64(seconds.min(86_400.0)))
}

/// The server's own message: a JSON `error` (string or `{message}`), `detail` or `message`
/// field, else the start of the body.
fn server_message(body: &str) -> String {
    if let Ok(value) = serde_json::from_str::<serde_json::Value>(body) {
        for key in ["error", "detail", "message"] {
            match value.get(key) {
                Some(serde_json::Value::String(text)) => return excerpt(text),
                Some(serde_json::Value::Object(inner)) => {
                    if let Some(serde_json::Value::String(text)) = inner.get("message") {
                        return excerpt(text);
                    }
                }
                _ => {}
            }
        }
    }
    if body.trim().is_empty() {
        "(empty body)".to_owned()
    } else {
        excerpt(body)
    }
}

fn excerpt(text: &str) -> String {
    let head: String = text.chars().take(300).collect();
    if head.len() < text.len() {
        format!("{head}...")
    } else {
        head
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn server_messages_are_found_in_common_shapes() {
        assert_eq!(server_message(r#"{"error":"bad image"}"#), "bad image");
        assert_eq!(
            server_message(r#"{"error":{"message":"too big","code":1}}"#),
            "too big"
        );
        assert_eq!(server_message(r#"{"detail":"nope"}"#), "nope");
        assert_eq!(server_message("plain text"), "plain text");
        assert_eq!(server_message(""), "(empty body)");
        assert!(server_message(&"x".repeat(1000)).ends_with("..."));
    }

    #[test]
    fn retry_after_accepts_seconds_only() {
        assert_eq!(parse_retry_after(" 2 "), Some(Duration::from_secs(2)));
        assert_eq!(parse_retry_after("0.5"), Some(Duration::from_millis(500)));
        assert_eq!(parse_retry_after("-1"), None);
        assert_eq!(parse_retry_after("Wed, 21 Oct 2015 07:28:00 GMT"), None);
    }
}
