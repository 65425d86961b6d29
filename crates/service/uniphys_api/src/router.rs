//! The router: every route registered with its OpenAPI operation (so the document covers every
//! route by construction), request tracing, request metrics through the hooks, and a JSON 404.

use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::extract::{MatchedPath, Request, State};
use axum::middleware::{self, Next};
use axum::response::Response;
use axum::{Extension, Router};
use tower_http::trace::TraceLayer;
use utoipa::openapi::security::{HttpAuthScheme, HttpBuilder, SecurityScheme};
use utoipa::{Modify, OpenApi};
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use crate::connections::{ConnectionLimits, serve_with_limits};
use crate::error::ApiError;
use crate::routes::ops::OpenApiJson;
use crate::routes::{
    artifacts, assets, batches, exports, import, jobs, ops, overview, submit, work,
};
use crate::state::Shared;
use crate::{ApiState, ServiceHooks};

#[derive(OpenApi)]
#[openapi(
    info(
        title = "UniPhys service API",
        description = "Submit 3D assets to the UniPhys pipeline, follow their stages, download results. \
                       Every /v1 route needs `Authorization: Bearer <api key>`; errors answer \
                       `{\"error\": {\"code\", \"message\"}}`."
    ),
    modifiers(&BearerKey),
    tags(
        (name = "assets", description = "Submit and inspect assets"),
        (name = "jobs", description = "Jobs: status, history, cancel, retry"),
        (name = "artifacts", description = "Stage outputs"),
        (name = "operations", description = "Statistics, health, metrics, this document"),
    )
)]
struct ApiDoc;

/// Declares the `api_key` bearer scheme the operations refer to.
struct BearerKey;

impl Modify for BearerKey {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        let components = openapi.components.get_or_insert_with(Default::default);
        components.add_security_scheme(
            "api_key",
            SecurityScheme::Http(HttpBuilder::new().scheme(HttpAuthScheme::Bearer).build()),
        );
    }
}

fn api_routes() -> OpenApiRouter<Shared> {
    OpenApiRouter::with_openapi(ApiDoc::openapi())
        .routes(routes!(submit::upload, assets::list))
        .routes(routes!(import::by_url))
        .routes(routes!(import::batch, batches::list))
        .routes(routes!(batches::stats))
        .routes(routes!(exports::start, exports::status))
        .routes(routes!(assets::get))
        .routes(routes!(artifacts::list))
        .routes(routes!(artifacts::download))
        .routes(routes!(jobs::get))
        .routes(routes!(jobs::events))
        .routes(routes!(jobs::cancel))
        .routes(routes!(jobs::retry))
        .routes(routes!(work::list))
        .routes(routes!(ops::stats))
        .routes(routes!(overview::overview))
        .routes(routes!(ops::healthz))
        .routes(routes!(ops::readyz))
        .routes(routes!(ops::metrics))
        .routes(routes!(ops::openapi))
}

/// The OpenAPI document of every route, generated from the handlers' annotations.
#[must_use]
pub fn openapi() -> utoipa::openapi::OpenApi {
    let (_, doc) = api_routes().split_for_parts();
    with_openapi_path_syntax(doc)
}

/// axum writes a catch-all segment `{*name}`; OpenAPI writes `{name}`.
fn with_openapi_path_syntax(mut doc: utoipa::openapi::OpenApi) -> utoipa::openapi::OpenApi {
    let paths = std::mem::take(&mut doc.paths.paths);
    doc.paths.paths = paths
        .into_iter()
        .map(|(path, item)| (path.replace("{*", "{"), item))
        .collect();
    doc
}

/// Serves `router(state)` on `listener` within the default [`ConnectionLimits`] until
/// `shutdown` completes, then finishes the requests in flight.
pub async fn serve(
    listener: tokio::net::TcpListener,
    state: ApiState,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    serve_with_limits(
        listener,
        router(state),
        ConnectionLimits::default(),
        shutdown,
    )
    .await
}

/// The API's router, ready to serve (`axum::serve(listener, router(state))`) or to call in tests.
pub fn router(state: ApiState) -> Router {
    let hooks = state.hooks.clone();
    let shared: Shared = Arc::new(state);
    if tokio::runtime::Handle::try_current().is_ok() {
        tokio::spawn(crate::board::sample_history(Arc::downgrade(&shared)));
    }
    let (router, doc) = api_routes().split_for_parts();
    let doc = with_openapi_path_syntax(doc);
    let json = doc
        .to_pretty_json()
        .unwrap_or_else(|e| format!("{{\"error\": \"openapi document: {e}\"}}"));
    router
        .merge(uniphys_dashboard::router())
        .fallback(not_found)
        .layer(Extension(OpenApiJson(Arc::new(json))))
        .layer(middleware::from_fn_with_state(shared.clone(), observe))
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(move |request: &Request| request_span(hooks.as_ref(), request))
                .on_response(record_status)
                // 5xx are logged once, where the error becomes a response.
                .on_failure(()),
        )
        .with_state(shared)
}

/// The span of one request: the hooks' (which may join the caller's trace), else the API's own.
fn request_span(hooks: &dyn ServiceHooks, request: &Request) -> tracing::Span {
    let route = request
        .extensions()
        .get::<MatchedPath>()
        .map_or("unmatched", MatchedPath::as_str);
    hooks
        .request_span(request.method(), route, request.headers())
        .unwrap_or_else(|| {
            tracing::info_span!(
                "http_request",
                http.request.method = %request.method(),
                http.route = route,
                http.response.status_code = tracing::field::Empty,
            )
        })
}

fn record_status(response: &Response, _latency: Duration, span: &tracing::Span) {
    span.record("http.response.status_code", response.status().as_u16());
    tracing::debug!(status = response.status().as_u16(), "response");
}

async fn not_found(request: Request) -> ApiError {
    ApiError::NotFound(format!(
        "no route {} {}",
        request.method(),
        request.uri().path()
    ))
}

/// Reports each request's route, status and duration to the hooks.
async fn observe(State(state): State<Shared>, request: Request, next: Next) -> Response {
    let started = Instant::now();
    let method = request.method().clone();
    let route = request
        .extensions()
        .get::<MatchedPath>()
        .map_or_else(|| "unmatched".to_owned(), |p| p.as_str().to_owned());
    let response = next.run(request).await;
    state.hooks.observe_request(
        method.as_str(),
        &route,
        response.status().as_u16(),
        started.elapsed(),
    );
    response
}
