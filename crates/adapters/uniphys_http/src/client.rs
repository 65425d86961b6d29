use std::io::Read;
use std::time::{Duration, Instant};

use reqwest::blocking::{Client, RequestBuilder, Response};

use crate::{Failure, FailureKind, HttpError, HttpResult, retry_after, server_message};

/// Settings of an [`HttpClient`].
#[derive(Debug, Clone, PartialEq)]
pub struct HttpConfig {
    /// Limit on opening a connection.
    pub connect_timeout: Duration,
    /// Limit on one attempt: sending, waiting for the answer and reading its body (the body is
    /// read in pieces; the limit is checked after each, and one piece waits at most this long).
    pub attempt_timeout: Duration,
    /// Largest response body read; a longer one is a permanent [`FailureKind::TooLarge`].
    pub max_response_bytes: u64,
    /// `User-Agent` sent with every request.
    pub user_agent: String,
    /// Idle connections kept per host for reuse.
    pub max_idle_per_host: usize,
}

impl Default for HttpConfig {
    /// 10 s to connect, 120 s per attempt, 16 MiB bodies, user agent `uniphys`, 8 idle
    /// connections per host.
    fn default() -> Self {
        Self {
            connect_timeout: Duration::from_secs(10),
            attempt_timeout: Duration::from_secs(120),
            max_response_bytes: 16 * 1024 * 1024,
            user_agent: "uniphys".to_owned(),
            max_idle_per_host: 8,
        }
    }
}

/// An answer read whole: its status, the wait its `Retry-After` (or `retry-after-ms`) asks for,
/// and its body as text (invalid UTF-8 replaced).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reply {
    /// HTTP status.
    pub status: u16,
    /// The server's requested wait, whatever the status.
    pub retry_after: Option<Duration>,
    /// The body.
    pub body: String,
}

impl Reply {
    /// The failure a non-2xx reply is, with the server's message ([`server_message`]) and its
    /// `Retry-After` if the status is 429 or 503; `None` for 2xx.
    #[must_use]
    pub fn failure(&self) -> Option<Failure> {
        (!(200..300).contains(&self.status))
            .then(|| Failure::status(self.status, server_message(&self.body), self.retry_after))
    }
}

/// The shared blocking HTTP client (`reqwest`): connection pool, connect and attempt timeouts,
/// body limit. Cheap to clone (clones share the pool); thread-safe. Build and drop it outside
/// async code (on a plain or blocking thread), as every blocking `reqwest` client.
#[derive(Debug, Clone)]
pub struct HttpClient {
    client: Client,
    config: HttpConfig,
}

impl HttpClient {
    /// A client with `config`.
    ///
    /// # Errors
    /// [`HttpError::InvalidOption`] for a zero timeout or body limit; [`HttpError::Build`] if
    /// the TLS backend or resolver cannot be set up.
    pub fn new(config: HttpConfig) -> HttpResult<Self> {
        let invalid = |name, value: String, expected| {
            Err(HttpError::InvalidOption {
                name,
                value,
                expected,
            })
        };
        if config.connect_timeout.is_zero() {
            return invalid("connect_timeout", "0 s".to_owned(), "more than zero");
        }
        if config.attempt_timeout.is_zero() {
            return invalid("attempt_timeout", "0 s".to_owned(), "more than zero");
        }
        if config.max_response_bytes == 0 {
            return invalid("max_response_bytes", "0".to_owned(), "at least 1");
        }
        let client = Client::builder()
            .connect_timeout(config.connect_timeout)
            .timeout(config.attempt_timeout)
            .pool_max_idle_per_host(config.max_idle_per_host)
            .user_agent(config.user_agent.clone())
            .build()
            .map_err(|error| HttpError::Build {
                reason: chain(&error),
            })?;
        Ok(Self { client, config })
    }

    /// The settings.
    #[must_use]
    pub fn config(&self) -> &HttpConfig {
        &self.config
    }

    /// The `reqwest` client, to build requests with.
    #[must_use]
    pub fn inner(&self) -> &Client {
        &self.client
    }

    /// One attempt: sends `request` (its timeout cut to `time_left` when given) and reads the
    /// answer whole, whatever its status.
    ///
    /// # Errors
    /// The transport's [`Failure`]: connect, timeout, interrupted (transient); too large,
    /// unsendable (permanent).
    pub fn exchange(
        &self,
        request: RequestBuilder,
        time_left: Option<Duration>,
    ) -> Result<Reply, Failure> {
        let limit = time_left.map_or(self.config.attempt_timeout, |left| {
            left.min(self.config.attempt_timeout)
        });
        let start = Instant::now();
        let response = request
            .timeout(limit)
            .send()
            .map_err(|error| self.transport_failure(&error, limit))?;
        let status = response.status().as_u16();
        let retry_after = retry_after::from_headers(response.headers());
        let body = self.read_body(response, start, limit)?;
        Ok(Reply {
            status,
            retry_after,
            body,
        })
    }

    /// One attempt that must succeed: [`HttpClient::exchange`], and a non-2xx answer is its
    /// [`Reply::failure`] (classed by [`crate::status_class`]).
    ///
    /// # Errors
    /// The attempt's [`Failure`].
    pub fn send(
        &self,
        request: RequestBuilder,
        time_left: Option<Duration>,
    ) -> Result<Reply, Failure> {
        let reply = self.exchange(request, time_left)?;
        match reply.failure() {
            Some(failure) => Err(failure),
            None => Ok(reply),
        }
    }

    fn read_body(
        &self,
        mut response: Response,
        start: Instant,
        limit: Duration,
    ) -> Result<String, Failure> {
        let max = self.config.max_response_bytes;
        let mut body = Vec::new();
        let mut chunk = [0u8; 64 * 1024];
        loop {
            let read = response.read(&mut chunk).map_err(|error| {
                let timed_out = error.kind() == std::io::ErrorKind::TimedOut
                    || std::error::Error::source(&error)
                        .and_then(|s| s.downcast_ref::<reqwest::Error>())
                        .is_some_and(reqwest::Error::is_timeout);
                if timed_out {
                    self.timeout_failure(limit)
                } else {
                    Failure::new(
                        FailureKind::Interrupted,
                        format!("the answer was cut off: {}", chain(&error)),
                    )
                }
            })?;
            if read == 0 {
                break;
            }
            body.extend_from_slice(&chunk[..read]);
            if body.len() as u64 > max {
                return Err(Failure::new(
                    FailureKind::TooLarge,
                    format!("the response body exceeds {max} bytes"),
                ));
            }
            if start.elapsed() > limit {
                return Err(self.timeout_failure(limit));
            }
        }
        Ok(String::from_utf8_lossy(&body).into_owned())
    }

    fn timeout_failure(&self, limit: Duration) -> Failure {
        Failure::new(
            FailureKind::Timeout,
            format!(
                "timed out: no complete answer within {} ms",
                limit.as_millis()
            ),
        )
    }

    fn transport_failure(&self, error: &reqwest::Error, limit: Duration) -> Failure {
        let target = error
            .url()
            .map_or_else(|| "the server".to_owned(), |url| url.as_str().to_owned());
        if error.is_builder() {
            return Failure::new(
                FailureKind::Unsendable,
                format!("the request to {target} cannot be sent: {}", chain(error)),
            );
        }
        if error.is_timeout() {
            return self.timeout_failure(limit);
        }
        if error.is_connect() {
            return Failure::new(
                FailureKind::Connect,
                format!("cannot reach {target}: {}", chain(error)),
            );
        }
        if error.is_redirect() {
            return Failure::new(FailureKind::Unsendable, chain(error));
        }
        Failure::new(
            FailureKind::Interrupted,
            format!("the connection to {target} broke: {}", chain(error)),
        )
    }
}

/// An error and its sources, joined by `: `.
fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let next = cause.to_string();
        if !text.contains(&next) {
            text.push_str(": ");
            text.push_str(&next);
        }
        source = cause.source();
    }
    text
}
