use std::time::Duration;

/// Whether trying again may succeed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// The same request may succeed later: retried under the policy.
    Transient,
    /// The same request would fail again: reported at once.
    Permanent,
}

/// What kind of thing failed in one attempt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureKind {
    /// No connection could be opened (refused, unreachable, DNS, connect timeout).
    Connect,
    /// The answer did not arrive within the attempt's time.
    Timeout,
    /// The connection broke during the exchange (closed without a reply, truncated body).
    Interrupted,
    /// The server answered with a status other than 2xx.
    Status,
    /// The body is larger than the client reads.
    TooLarge,
    /// The body arrived but is not the expected answer (judged by the client).
    Body,
    /// The request cannot be sent at all (bad URL, unsupported scheme).
    Unsendable,
}

/// The failure of one attempt: its kind and class, the HTTP status if there was one, what
/// happened, and the server's `Retry-After` when it is honoured (429 and 503).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Failure {
    /// What failed.
    pub kind: FailureKind,
    /// Transient or permanent.
    pub class: Class,
    /// HTTP status of the answer, if one came.
    pub status: Option<u16>,
    /// What happened (for a status: the server's message).
    pub detail: String,
    /// The server's requested wait (429 and 503 only).
    pub retry_after: Option<Duration>,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.kind, self.status) {
            (FailureKind::Status, Some(status)) => write!(f, "HTTP {status}: {}", self.detail),
            (FailureKind::Body | FailureKind::TooLarge, Some(status)) => {
                write!(f, "{} (HTTP {status})", self.detail)
            }
            _ => f.write_str(&self.detail),
        }
    }
}

impl Failure {
    /// A failure of `kind` with the class it has by default: connect errors, timeouts and
    /// interruptions transient; bodies, oversized answers and unsendable requests permanent.
    /// (Use [`Failure::status`] for an HTTP status.)
    #[must_use]
    pub fn new(kind: FailureKind, detail: impl Into<String>) -> Self {
        let class = match kind {
            FailureKind::Connect | FailureKind::Timeout | FailureKind::Interrupted => {
                Class::Transient
            }
            FailureKind::Status
            | FailureKind::TooLarge
            | FailureKind::Body
            | FailureKind::Unsendable => Class::Permanent,
        };
        Self {
            kind,
            class,
            status: None,
            detail: detail.into(),
            retry_after: None,
        }
    }

    /// An answer with non-2xx `status`, classed by [`status_class`]; `retry_after` is kept only
    /// for 429 and 503.
    #[must_use]
    pub fn status(status: u16, message: impl Into<String>, retry_after: Option<Duration>) -> Self {
        Self {
            kind: FailureKind::Status,
            class: status_class(status).unwrap_or(Class::Permanent),
            status: Some(status),
            detail: message.into(),
            retry_after: retry_after.filter(|_| matches!(status, 429 | 503)),
        }
    }

    /// A body that is not the expected answer: permanent unless marked [`Failure::transient`].
    #[must_use]
    pub fn body(detail: impl Into<String>) -> Self {
        Self::new(FailureKind::Body, detail)
    }

    /// The same failure, classed transient (a client that retries, say, malformed bodies).
    #[must_use]
    pub fn transient(self) -> Self {
        Self {
            class: Class::Transient,
            ..self
        }
    }

    /// Whether the policy may retry it.
    #[must_use]
    pub fn is_transient(&self) -> bool {
        self.class == Class::Transient
    }
}

/// The class of an HTTP status: `None` for success (2xx), transient for 408, 425, 429, 500,
/// 502, 503 and 504, permanent for everything else (other 4xx, 501, 505 and up, 1xx, 3xx).
#[must_use]
pub fn status_class(status: u16) -> Option<Class> {
    match status {
        200..=299 => None,
        408 | 425 | 429 | 500 | 502 | 503 | 504 => Some(Class::Transient),
        _ => Some(Class::Permanent),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statuses_are_classed_as_the_policy_says() {
        for status in [200, 201, 204, 299] {
            assert_eq!(status_class(status), None, "{status}");
        }
        for status in [408, 425, 429, 500, 502, 503, 504] {
            assert_eq!(status_class(status), Some(Class::Transient), "{status}");
        }
        for status in [301, 400, 401, 403, 404, 409, 413, 422, 501, 505, 599] {
            assert_eq!(status_class(status), Some(Class::Permanent), "{status}");
        }
    }

    #[test]
    fn transport_failures_are_transient_and_bodies_permanent_unless_marked() {
        assert!(Failure::new(FailureKind::Connect, "refused").is_transient());
        assert!(Failure::new(FailureKind::Timeout, "slow").is_transient());
        assert!(Failure::new(FailureKind::Interrupted, "cut").is_transient());
        assert!(!Failure::new(FailureKind::Unsendable, "ftp://").is_transient());
        assert!(!Failure::new(FailureKind::TooLarge, "big").is_transient());
        assert!(!Failure::body("not JSON").is_transient());
        assert!(Failure::body("not JSON").transient().is_transient());
    }

    #[test]
    fn retry_after_is_kept_only_on_429_and_503() {
        let wait = Some(Duration::from_secs(3));
        assert_eq!(Failure::status(429, "slow down", wait).retry_after, wait);
        assert_eq!(Failure::status(503, "busy", wait).retry_after, wait);
        assert_eq!(Failure::status(500, "oops", wait).retry_after, None);
        assert_eq!(Failure::status(408, "late", wait).retry_after, None);
    }

    #[test]
    fn a_status_failure_prints_its_status_and_message() {
        let failure = Failure::status(503, "overloaded", None);
        assert!(failure.is_transient());
        assert_eq!(failure.to_string(), "HTTP 503: overloaded");
        assert!(!Failure::status(404, "no such path", None).is_transient());
    }
}
