//! The recording format: exchanges matched by method, path and body substrings, each with
//! replies played in order (the last one repeats).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

use serde::{Deserialize, Serialize};

use crate::{RecordedRequest, ReplayError, ReplayResult, Reply};

/// A recorded conversation with one service: the exchanges it knows.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recording {
    /// Tried in order; the first one matching a request answers it.
    pub exchanges: Vec<Exchange>,
}

/// Requests of one kind and the replies to play to them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Exchange {
    /// HTTP method, compared case-insensitively (`"POST"`).
    pub method: String,
    /// Request path. Without a `?` it is compared with the request's path without its query;
    /// with a `?` with the whole request target.
    pub path: String,
    /// Every substring must occur in the request body (empty = any body).
    #[serde(default)]
    pub body_contains: Vec<String>,
    /// Played in order for successive matching requests; the last one repeats. At least one.
    pub replies: Vec<Reply>,
}

impl Exchange {
    /// Whether `request` is one of this exchange's requests.
    #[must_use]
    pub fn matches(&self, request: &RecordedRequest) -> bool {
        if !self.method.eq_ignore_ascii_case(&request.method) {
            return false;
        }
        let target = if self.path.contains('?') {
            request.path.as_str()
        } else {
            request.path.split('?').next().unwrap_or_default()
        };
        if target != self.path {
            return false;
        }
        if self.body_contains.is_empty() {
            return true;
        }
        let body = String::from_utf8_lossy(&request.body);
        self.body_contains.iter().all(|part| body.contains(part))
    }
}

impl Recording {
    /// Reads and checks a recording file (JSON).
    ///
    /// # Errors
    /// [`ReplayError::Read`], [`ReplayError::Parse`] or [`ReplayError::Invalid`].
    pub fn load(path: impl AsRef<Path>) -> ReplayResult<Self> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| ReplayError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses and checks a recording from JSON text.
    ///
    /// # Errors
    /// [`ReplayError::Parse`] or [`ReplayError::Invalid`].
    pub fn from_json(text: &str) -> ReplayResult<Self> {
        Self::parse(text, "<string>")
    }

    fn parse(text: &str, origin: &str) -> ReplayResult<Self> {
        let recording: Self = serde_json::from_str(text).map_err(|source| ReplayError::Parse {
            origin: origin.to_owned(),
            source,
        })?;
        recording.check(origin)?;
        Ok(recording)
    }

    /// Checks that every exchange can be played: a method, a path starting with `/`, a reply.
    ///
    /// # Errors
    /// [`ReplayError::Invalid`] naming the first exchange that cannot.
    pub fn check(&self, origin: &str) -> ReplayResult<()> {
        for (index, exchange) in self.exchanges.iter().enumerate() {
            let reason = if exchange.method.trim().is_empty() {
                Some("has no method")
            } else if !exchange.path.starts_with('/') {
                Some("has a path that does not start with '/'")
            } else if exchange.replies.is_empty() {
                Some("has no replies")
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(ReplayError::Invalid {
                    origin: origin.to_owned(),
                    reason: format!(
                        "exchange {index} ({} {}) {reason}",
                        exchange.method, exchange.path
                    ),
                });
            }
        }
        Ok(())
    }

    /// A responder playing this recording: per exchange, the n-th matching request gets reply
    /// `min(n, replies - 1)`; unmatched requests get [`Reply::unmatched`].
    #[must_use]
    pub fn into_responder(self) -> crate::Responder {
        let played = Mutex::new(BTreeMap::<usize, usize>::new());
        Arc::new(move |request: &RecordedRequest| {
            let Some((index, exchange)) = self
                .exchanges
                .iter()
                .enumerate()
                .find(|(_, exchange)| exchange.matches(request))
            else {
                return Reply::unmatched(request);
            };
            let mut played = played
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let count = played.entry(index).or_insert(0);
            let reply_index = (*count).min(exchange.replies.len().saturating_sub(1));
            *count += 1;
            exchange
                .replies
                .get(reply_index)
                .cloned()
                .unwrap_or_else(|| Reply::unmatched(request))
        })
    }
}
