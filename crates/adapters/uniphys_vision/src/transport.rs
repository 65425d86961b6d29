//! One retrying JSON request under the shared policy (`uniphys_http`), used by both clients.

use serde::Serialize;
use serde::de::DeserializeOwned;
use uniphys_http::{Failure, FailureKind, HttpClient, HttpConfig, HttpError, RetryPolicy};

use crate::{ClientConfig, VisionError, VisionResult};

/// A configured HTTP client for one service.
#[derive(Debug)]
pub(crate) struct Transport {
    config: ClientConfig,
    http: HttpClient,
    policy: RetryPolicy,
    service: &'static str,
}

impl Transport {
    pub(crate) fn new(config: ClientConfig, service: &'static str) -> VisionResult<Self> {
        config.check(service)?;
        let http = HttpClient::new(HttpConfig {
            connect_timeout: config.connect_timeout,
            attempt_timeout: config.request_timeout,
            max_response_bytes: config.max_response_bytes,
            user_agent: format!("uniphys-vision-{service}"),
            ..HttpConfig::default()
        })
        .map_err(|error| VisionError::InvalidOption {
            service,
            name: "http client",
            value: error.to_string(),
            expected: "settings the HTTP client accepts",
        })?;
        let policy = config.retry_policy();
        Ok(Self {
            config,
            http,
            policy,
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
        let request = self.http.inner().get(self.url(path));
        match self.http.send(request, None) {
            Ok(_) => Ok(()),
            Err(failure) if failure.is_transient() => Err(VisionError::Unhealthy {
                service: self.service,
                base_url: self.config.base_url.clone(),
                timeout: self.config.request_timeout,
                reason: failure.to_string(),
            }),
            Err(failure) => Err(self.permanent(path, failure)),
        }
    }

    /// `POST path` with `request` as JSON under the shared policy (connection errors, timeouts,
    /// 408/425/429/500/502/503/504 and interrupted answers are retried); a body that is not
    /// JSON is retried too, but an answer that is JSON and does not fit `T` is a contract
    /// violation and is not.
    pub(crate) fn post<Q: Serialize, T: DeserializeOwned>(
        &self,
        path: &'static str,
        request: &Q,
    ) -> VisionResult<T> {
        let body = serde_json::to_vec(request).map_err(|error| VisionError::InvalidInput {
            service: self.service,
            reason: format!("the request cannot be serialised: {error}"),
        })?;
        let url = self.url(path);
        let answer = self.http.send_with_retry(
            &self.policy,
            &body,
            |http| {
                http.post(&url)
                    .header("content-type", "application/json")
                    .body(body.clone())
            },
            |reply| {
                let value =
                    serde_json::from_str::<serde_json::Value>(&reply.body).map_err(|error| {
                        Failure::body(format!(
                            "malformed JSON answer ({error}): {}",
                            uniphys_http::excerpt(&reply.body, 300)
                        ))
                        .transient()
                    })?;
                serde_json::from_value(value).map_err(|error| Failure::body(error.to_string()))
            },
            |_| {},
        );
        answer.map_err(|error| match error {
            HttpError::GaveUp { attempts, last, .. } => VisionError::GaveUp {
                service: self.service,
                path,
                base_url: self.config.base_url.clone(),
                attempts,
                reason: last.to_string(),
            },
            HttpError::Permanent { failure } => self.permanent(path, failure),
            other => VisionError::Transport {
                service: self.service,
                url: url.clone(),
                reason: other.to_string(),
            },
        })
    }

    /// The error of a failure retrying would not change.
    fn permanent(&self, path: &'static str, failure: Failure) -> VisionError {
        match (failure.kind, failure.status) {
            (FailureKind::Status, Some(status)) => VisionError::Refused {
                service: self.service,
                path,
                status,
                message: failure.detail,
            },
            (FailureKind::Body, _) => VisionError::InvalidAnswer {
                service: self.service,
                path,
                reason: failure.detail,
            },
            _ => VisionError::Transport {
                service: self.service,
                url: self.url(path),
                reason: failure.to_string(),
            },
        }
    }
}
