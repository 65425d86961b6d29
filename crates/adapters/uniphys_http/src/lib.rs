//! One error and retry policy for the blocking clients of the external model services (LVLM,
//! SAM/PartField vision, UniPhysGen), over one HTTP client (`reqwest`, blocking).
//!
//! - [`Failure`] and [`Class`]: what went wrong in one attempt, transient or permanent
//!   ([`status_class`]: 408, 425, 429, 500, 502, 503 and 504 are transient, other 4xx and 5xx
//!   permanent; connect errors, timeouts and interrupted answers transient; a body that cannot
//!   be used is permanent unless a client marks it transient).
//! - [`RetryPolicy`]: attempts, exponential backoff with jitter ([`unit_jitter`]), the cap that
//!   also bounds a server's `Retry-After` ([`parse_retry_after`], honoured on 429 and 503), an
//!   optional overall deadline; [`RetryPolicy::run`] is the retry loop for clients that do work
//!   around each attempt (budgets, permits, GPU slots).
//! - [`HttpClient`]: the shared `reqwest::blocking::Client` with connect and attempt timeouts
//!   and a body limit ([`HttpConfig`]); [`HttpClient::send`] is one attempt,
//!   [`HttpClient::send_with_retry`] the whole policy.
//! - [`AttemptReport`]: every attempt, handed to the caller's callback to log or record.

mod client;
mod error;
mod failure;
mod jitter;
mod message;
mod policy;
mod retry;
mod retry_after;
mod send;

pub use client::{HttpClient, HttpConfig, Reply};
pub use error::{HttpError, HttpResult};
pub use failure::{Class, Failure, FailureKind, status_class};
pub use jitter::unit_jitter;
pub use message::{excerpt, server_message};
pub use policy::RetryPolicy;
pub use retry::{Attempt, AttemptOutcome, AttemptReport, Step};
pub use retry_after::{MAX_RETRY_AFTER, parse_retry_after};

/// The blocking `reqwest` types the clients build requests with.
pub use reqwest::blocking::{Client as ReqwestClient, RequestBuilder};
