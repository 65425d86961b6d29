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
//! | route | what |
//! |---|---|
//! | `POST /v1/assets?filename=&priority=` | upload (body = file bytes, streamed, size-capped): 201 new, 200 same content again |
//! | `POST /v1/assets/by-url` | import an object under the tenant's prefixes (`incoming/t{n}/`, `sources/t{n}/`) |
//! | `POST /v1/batches` | `{"items": [{url, filename?, priority?}]}`: all validated first, then per-item results |
//! | `GET /v1/assets?state=&asset=&before=&limit=` | jobs newest first, keyset pages (`next`) |
//! | `GET /v1/assets/{asset_id}` | asset, latest job, each stage (state, attempts, errors, timings, cost, progress) |
//! | `GET /v1/assets/{asset_id}/artifacts[/{stage}/{name}]` | artifacts of succeeded stages; streamed download |
//! | `GET /v1/jobs/{job_id}[/events]`, `POST /v1/jobs/{job_id}/cancel`, `.../retry` | job status, history, control |
//! | `GET /v1/stats` | per stage: depth, running, failed, throughput, oldest waiting age |
//! | `GET /v1/overview?since_ms=` | the dashboard's poll: cached statistics, the tenant's jobs by state, history samples |
//! | `GET /v1/work?state=running\|dead` | open or dead-lettered stage runs of the newest jobs, with last error and progress |
//! | `GET /v1/batches`, `GET /v1/batches/{batch}/stats` | batch labels; a batch's dataset statistics |
//! | `POST`, `GET /v1/batches/{batch}/export` | write the batch as a UniPhys-40K dataset into the object store (background); its progress |
//! | `GET /healthz`, `/readyz`, `/metrics`, `/openapi.json` | operations (no key) |
//! | `GET /`, `/ui/...` | the dashboard's static files (no key; the pages ask for one) |
//!
//! Ids are answered as `asset_12`, `job_7`; paths accept `asset_12` or `12`.
//!
//! - `config.rs`: [`ApiConfig`], limits and the stage graph of submissions.
//! - `connections.rs`: [`serve_with_limits`], the accept loop with a deadline for a request's
//!   headers and a cap on one address's connections ([`ConnectionLimits`]).
//! - `hooks.rs`: [`ServiceHooks`], [`NoHooks`].
//! - `state.rs`: [`ApiState`].
//! - `router.rs`: [`router`], [`openapi`], tracing and request metrics.
//! - `error.rs`: [`ApiError`] and its mapping to statuses.
//! - `extract.rs`: tenant, JSON, query and path extractors answering in the error format.
//! - `ids.rs`, `page.rs`, `upload.rs`, `views.rs`: ids in paths, page limits and cursors,
//!   spooling uploads, answer shapes.
//! - `backlog_gauge.rs`: each tenant's backlog counted at most once a second plus what this
//!   process submitted since, so the cap is checked exactly only near it.
//! - `board.rs`, `ttl_cache.rs`: the dashboard's shared statistics, history sampler, and the
//!   per-tenant counts and batch statistics cached for a few seconds.
//! - `dataset_stats.rs`: [`DatasetStats`] of a batch from its `convert` summaries.
//! - `dataset_layout.rs`: [`dataset_layout`], the UniPhys-40K layout of an exported batch (entity
//!   names, type folders, the index and failure tables), shared with `uniphys dataset export`.
//! - `dataset_export.rs`: [`DatasetExportView`] and the background export of a batch into the
//!   object store.
//! - `routes/`: the handlers, one file per resource.

mod backlog_gauge;
mod board;
mod config;
mod connections;
mod dataset_export;
pub mod dataset_layout;
mod dataset_stats;
mod error;
mod extract;
mod hooks;
mod ids;
mod page;
mod router;
mod routes;
mod state;
mod ttl_cache;
mod upload;
mod views;

pub use config::{ApiConfig, DEFAULT_MAX_UPLOAD_BYTES};
pub use connections::{ConnectionLimits, serve_with_limits};
pub use dataset_export::DatasetExportView;
pub use dataset_stats::{DatasetStats, Distribution, dataset_stats};
pub use error::{ApiError, ApiResult, ErrorBody, ErrorDetail};
pub use hooks::{BoxFuture, MetricsText, NoHooks, ReadinessCheck, ServiceHooks};
pub use router::{openapi, router, serve};
pub use state::ApiState;
