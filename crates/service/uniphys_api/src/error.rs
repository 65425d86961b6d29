//! The crate's one error enum, and the one place it becomes an HTTP answer (house style E3).
//!
//! Every 4xx explains what to fix; a 5xx answers a generic message and is logged once, here.

use axum::Json;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use uniphys_queue::{QueueError, QueueErrorKind};
use uniphys_storage::StorageError;
use utoipa::ToSchema;

/// Result of handlers and helpers.
pub type ApiResult<T> = Result<T, ApiError>;

/// Seconds a client should wait after a 503 before trying again.
pub(crate) const UNAVAILABLE_RETRY_AFTER_SECS: u64 = 5;
/// `Retry-After` of a 429 from a full backlog when the route does not set its own, seconds.
const BUSY_RETRY_AFTER_SECS: u64 = 30;

/// Why a request failed; each variant is one HTTP status.
#[derive(Debug, thiserror::Error)]
pub enum ApiError {
    /// 400: the request is malformed (bad JSON, unknown field, invalid id, bad query).
    #[error("{message}")]
    BadRequest {
        /// Machine-readable reason (`invalid_json`, `invalid_id`, …).
        code: &'static str,
        /// What to fix.
        message: String,
    },
    /// 401: no API key, or one that is unknown or revoked.
    #[error("{0}")]
    Unauthorized(String),
    /// 404: no such row for this tenant (another tenant's rows are not told apart).
    #[error("{0}")]
    NotFound(String),
    /// 409: the row's state forbids the operation.
    #[error("{0}")]
    Conflict(String),
    /// 408: the request's body stopped arriving.
    #[error("{0}")]
    RequestTimeout(String),
    /// 413: the upload is larger than the configured limit.
    #[error("{0}")]
    PayloadTooLarge(String),
    /// 415: a file of a type the pipeline does not read.
    #[error("{0}")]
    UnsupportedMediaType(String),
    /// 422: well-formed, but it cannot be acted on (missing object, bad filename).
    #[error("{0}")]
    Unprocessable(String),
    /// 429: the tenant's backlog is at its cap; retry after `retry_after_secs`.
    #[error("{message}")]
    Backpressure {
        /// What is full.
        message: String,
        /// Seconds to wait.
        retry_after_secs: u64,
    },
    /// 503: the database or the object store is unreachable or saturated.
    #[error("service unavailable: {0}")]
    Unavailable(String),
    /// 500: a bug or a broken deployment; the detail is logged, not answered.
    #[error("internal error: {0}")]
    Internal(String),
}

/// The body of every error answer: `{ "error": { "code": ..., "message": ... } }`.
#[derive(Debug, Serialize, ToSchema)]
pub struct ErrorBody {
    /// The error.
    pub error: ErrorDetail,
}

/// Code and message of an error answer.
#[derive(Debug, Serialize, ToSchema)]
pub struct ErrorDetail {
    /// Machine-readable reason, stable across releases.
    pub code: String,
    /// What went wrong and what to fix, for people.
    pub message: String,
}

impl ApiError {
    /// A 400 with `code` and `message`.
    pub(crate) fn bad_request(code: &'static str, message: impl Into<String>) -> Self {
        Self::BadRequest {
            code,
            message: message.into(),
        }
    }

    fn status(&self) -> StatusCode {
        match self {
            Self::BadRequest { .. } => StatusCode::BAD_REQUEST,
            Self::Unauthorized(_) => StatusCode::UNAUTHORIZED,
            Self::NotFound(_) => StatusCode::NOT_FOUND,
            Self::Conflict(_) => StatusCode::CONFLICT,
            Self::RequestTimeout(_) => StatusCode::REQUEST_TIMEOUT,
            Self::PayloadTooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            Self::UnsupportedMediaType(_) => StatusCode::UNSUPPORTED_MEDIA_TYPE,
            Self::Unprocessable(_) => StatusCode::UNPROCESSABLE_ENTITY,
            Self::Backpressure { .. } => StatusCode::TOO_MANY_REQUESTS,
            Self::Unavailable(_) => StatusCode::SERVICE_UNAVAILABLE,
            Self::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }

    fn code(&self) -> &'static str {
        match self {
            Self::BadRequest { code, .. } => code,
            Self::Unauthorized(_) => "unauthorized",
            Self::NotFound(_) => "not_found",
            Self::Conflict(_) => "conflict",
            Self::RequestTimeout(_) => "request_timeout",
            Self::PayloadTooLarge(_) => "payload_too_large",
            Self::UnsupportedMediaType(_) => "unsupported_media_type",
            Self::Unprocessable(_) => "unprocessable",
            Self::Backpressure { .. } => "backlog_full",
            Self::Unavailable(_) => "unavailable",
            Self::Internal(_) => "internal",
        }
    }

    fn retry_after_secs(&self) -> Option<u64> {
        match self {
            Self::Backpressure {
                retry_after_secs, ..
            } => Some(*retry_after_secs),
            Self::Unavailable(_) => Some(UNAVAILABLE_RETRY_AFTER_SECS),
            _ => None,
        }
    }

    /// The status and body this error answers (also used for per-item batch results).
    pub(crate) fn to_body(&self) -> (StatusCode, ErrorBody) {
        let status = self.status();
        let message = if status.is_server_error() {
            match self {
                Self::Unavailable(_) => {
                    "the service is temporarily unavailable; retry later".into()
                }
                _ => "internal error; the server logged the details".into(),
            }
        } else {
            self.to_string()
        };
        let body = ErrorBody {
            error: ErrorDetail {
                code: self.code().to_owned(),
                message,
            },
        };
        (status, body)
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let (status, body) = self.to_body();
        if status.is_server_error() {
            tracing::error!(status = status.as_u16(), error = %self, "request failed");
        }
        let mut response = (status, Json(body)).into_response();
        if let Some(secs) = self.retry_after_secs() {
            response
                .headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(secs));
        }
        if status == StatusCode::UNAUTHORIZED {
            response
                .headers_mut()
                .insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        response
    }
}

impl From<QueueError> for ApiError {
    fn from(e: QueueError) -> Self {
        match e.kind() {
            QueueErrorKind::NotFound => Self::NotFound(e.to_string()),
            QueueErrorKind::Conflict | QueueErrorKind::Fenced => Self::Conflict(e.to_string()),
            QueueErrorKind::InvalidInput => Self::Unprocessable(e.to_string()),
            QueueErrorKind::Busy => Self::Backpressure {
                message: format!("{e}; retry later"),
                retry_after_secs: BUSY_RETRY_AFTER_SECS,
            },
            QueueErrorKind::Unavailable => Self::Unavailable(error_chain(&e)),
            QueueErrorKind::Internal => Self::Internal(error_chain(&e)),
        }
    }
}

impl From<StorageError> for ApiError {
    fn from(e: StorageError) -> Self {
        match e {
            StorageError::NotFound { key } => Self::NotFound(format!("no object at {key}")),
            StorageError::Conflict { .. } => Self::Conflict(e.to_string()),
            StorageError::Store { .. } => Self::Unavailable(error_chain(&e)),
            _ => Self::Internal(error_chain(&e)),
        }
    }
}

/// `e: cause: cause …`, for logs.
pub(crate) fn error_chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn server_errors_hide_their_detail_and_client_errors_explain() {
        let (status, body) = ApiError::Internal("secret path /var/x".into()).to_body();
        assert_eq!(status, StatusCode::INTERNAL_SERVER_ERROR);
        assert!(!body.error.message.contains("secret"));
        let (status, body) = ApiError::Conflict("cannot cancel job_1".into()).to_body();
        assert_eq!(status, StatusCode::CONFLICT);
        assert_eq!(body.error.message, "cannot cancel job_1");
        assert_eq!(body.error.code, "conflict");
    }

    #[test]
    fn backpressure_and_unavailability_say_when_to_retry() {
        let busy = ApiError::Backpressure {
            message: "full".into(),
            retry_after_secs: 7,
        }
        .into_response();
        assert_eq!(busy.status(), StatusCode::TOO_MANY_REQUESTS);
        assert_eq!(busy.headers()[header::RETRY_AFTER], "7");
        let down = ApiError::Unavailable("pool timed out".into()).into_response();
        assert_eq!(down.status(), StatusCode::SERVICE_UNAVAILABLE);
        assert!(down.headers().contains_key(header::RETRY_AFTER));
    }

    #[test]
    fn queue_errors_map_by_kind() {
        let e = ApiError::from(QueueError::Database(sqlx::Error::PoolTimedOut));
        assert!(matches!(e, ApiError::Unavailable(_)));
        let e = ApiError::from(QueueError::InvalidTransition {
            action: "cancel",
            id: "job_1".into(),
            state: "succeeded".into(),
        });
        assert!(matches!(e, ApiError::Conflict(m) if m.contains("succeeded")));
    }
}
