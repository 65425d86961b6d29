//! One recorded answer: status, headers, body, delay and an optional fault.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::RecordedRequest;

/// A fault played instead of (or in the middle of) a normal answer.
///
/// In JSON: `{"kind": "hang"}`, `{"kind": "truncate", "keep_bytes": 10}`,
/// `{"kind": "close_without_reply"}`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Fault {
    /// Never answer; hold the socket until the client gives up or the server stops.
    Hang,
    /// Send the status line and headers with the full `Content-Length`, then only the first
    /// `keep_bytes` bytes of the body, then close the connection.
    Truncate {
        /// Body bytes actually sent.
        keep_bytes: usize,
    },
    /// Close the connection without sending anything.
    CloseWithoutReply,
}

/// One answer of the replay server.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Reply {
    /// HTTP status (200 if absent).
    #[serde(default = "default_status")]
    pub status: u16,
    /// Extra response headers (`Content-Length` and `Connection` are set by the server).
    #[serde(default)]
    pub headers: BTreeMap<String, String>,
    /// Body text (used when `json` is absent).
    #[serde(default)]
    pub body: Option<String>,
    /// JSON body, serialised compactly; sets `Content-Type: application/json` unless a
    /// content type is given in `headers`.
    #[serde(default)]
    pub json: Option<serde_json::Value>,
    /// Wait before answering, milliseconds (cut short when the server stops).
    #[serde(default)]
    pub delay_ms: u64,
    /// A fault to play instead of a normal answer.
    #[serde(default)]
    pub fault: Option<Fault>,
}

fn default_status() -> u16 {
    200
}

impl Default for Reply {
    fn default() -> Self {
        Self {
            status: 200,
            headers: BTreeMap::new(),
            body: None,
            json: None,
            delay_ms: 0,
            fault: None,
        }
    }
}

impl Reply {
    /// A JSON answer with `status`.
    #[must_use]
    pub fn json(status: u16, value: serde_json::Value) -> Self {
        Self {
            status,
            json: Some(value),
            ..Self::default()
        }
    }

    /// A plain-text answer with `status`.
    #[must_use]
    pub fn text(status: u16, body: impl Into<String>) -> Self {
        Self {
            status,
            body: Some(body.into()),
            ..Self::default()
        }
    }

    /// A reply that plays `fault`.
    #[must_use]
    pub fn fault(fault: Fault) -> Self {
        Self {
            fault: Some(fault),
            ..Self::default()
        }
    }

    /// The same reply with one more header.
    #[must_use]
    pub fn with_header(mut self, name: impl Into<String>, value: impl Into<String>) -> Self {
        self.headers.insert(name.into(), value.into());
        self
    }

    /// The same reply, sent after `delay_ms` milliseconds.
    #[must_use]
    pub fn with_delay_ms(mut self, delay_ms: u64) -> Self {
        self.delay_ms = delay_ms;
        self
    }

    /// The answer to a request no exchange matches: 501 with a JSON body naming it.
    #[must_use]
    pub fn unmatched(request: &RecordedRequest) -> Self {
        Self::json(
            501,
            serde_json::json!({
                "error": "no recorded exchange matches this request",
                "method": request.method,
                "path": request.path,
            }),
        )
    }

    /// The body bytes: `json` serialised if present, else `body`, else empty.
    #[must_use]
    pub fn body_bytes(&self) -> Vec<u8> {
        match (&self.json, &self.body) {
            (Some(value), _) => value.to_string().into_bytes(),
            (None, Some(text)) => text.clone().into_bytes(),
            (None, None) => Vec::new(),
        }
    }

    /// Whether the headers already name a content type.
    #[must_use]
    pub fn has_content_type(&self) -> bool {
        self.headers
            .keys()
            .any(|name| name.eq_ignore_ascii_case("content-type"))
    }
}
