//! HTTP API of the UniPhys service (axum + tower), as a library: [`router`] builds the routes
//! over an [`ApiState`] (the queue store, the artifact store, the [`ApiConfig`] and the
//! [`ServiceHooks`] through which the binary plugs in the doorbell, progress, metrics and trace
//! context), and [`openapi`] returns the document generated from the handlers.
//!
//! Every `/v1` route authenticates `Authorization: Bearer <api key>` to a tenant; a tenant never
//! sees another tenant's assets, jobs or artifacts (they answer 404, as missing ones do). Every
//! error answers `{"error": {"code", "message"}}` with one status per [`ApiError`] variant;
//! 429 (backlog cap) and 503 (database or object store unavailable) carry `Retry-After`.
//!
//! - `config.rs`: [`ApiConfig`], limits and the stage graph of submissions.
//! - `hooks.rs`: [`ServiceHooks`], [`NoHooks`].
//! - `state.rs`: [`ApiState`].
//! - `router.rs`: [`router`], [`openapi`], tracing and request metrics.
//! - `error.rs`: [`ApiError`] and its mapping to statuses.
//! - `extract.rs`: tenant, JSON, query and path extractors answering in the error format.
//! - `ids.rs`, `upload.rs`, `views.rs`: ids in paths, spooling uploads, answer shapes.
//! - `routes/`: the handlers, one file per resource.

mod config;
mod error;
mod extract;
mod hooks;
mod ids;
mod router;
mod routes;
mod state;
mod upload;
mod views;

pub use config::{ApiConfig, DEFAULT_MAX_UPLOAD_BYTES};
pub use error::{ApiError, ApiResult, ErrorBody, ErrorDetail};
pub use hooks::{BoxFuture, MetricsText, NoHooks, ReadinessCheck, ServiceHooks};
pub use router::{openapi, router, serve};
pub use state::ApiState;
