//! The OpenAPI document, health, readiness, metrics, statistics and database outages.

use std::collections::BTreeSet;
use std::sync::atomic::Ordering;
use std::time::Duration;

use axum::body::Body;
use axum::http::{Method, StatusCode, header};
use serde_json::Value;
use uniphys_api::ApiConfig;
use uniphys_queue::Backend;

use crate::harness::{KEY, TestApp};

/// Every route the router serves, as `METHOD path` in OpenAPI syntax.
const ROUTES: &[&str] = &[
    "GET /healthz",
    "GET /metrics",
    "GET /openapi.json",
    "GET /readyz",
    "GET /v1/assets",
    "POST /v1/assets",
    "POST /v1/assets/by-url",
    "GET /v1/assets/{asset_id}",
    "GET /v1/assets/{asset_id}/artifacts",
    "GET /v1/assets/{asset_id}/artifacts/{name}",
    "GET /v1/batches",
    "POST /v1/batches",
    "GET /v1/batches/{batch}/export",
    "POST /v1/batches/{batch}/export",
    "GET /v1/batches/{batch}/stats",
    "GET /v1/jobs/{job_id}",
    "POST /v1/jobs/{job_id}/cancel",
    "GET /v1/jobs/{job_id}/events",
    "POST /v1/jobs/{job_id}/retry",
    "GET /v1/overview",
    "GET /v1/stats",
    "GET /v1/work",
];

pub async fn the_openapi_document_lists_every_route(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let answer = app
        .send(Method::GET, "/openapi.json", None, &[], Body::empty())
        .await;
    assert_eq!(answer.status, StatusCode::OK);
    let doc = answer.json();
    assert!(doc["openapi"].as_str().expect("version").starts_with("3."));
    let mut listed = BTreeSet::new();
    for (path, item) in doc["paths"].as_object().expect("paths") {
        for method in item.as_object().expect("path item").keys() {
            listed.insert(format!("{} {path}", method.to_uppercase()));
        }
    }
    let expected: BTreeSet<String> = ROUTES.iter().map(|r| (*r).to_owned()).collect();
    assert_eq!(listed, expected);
    // Each documented route is served (a request to it is not the router's 404).
    for route in ROUTES {
        let (method, path) = route.split_once(' ').expect("METHOD path");
        let uri = path
            .replace("{asset_id}", "asset_1")
            .replace("{job_id}", "job_1")
            .replace("{batch}", "x")
            .replace("{name}", "ingest/x.json");
        let method: Method = method.parse().expect("method");
        let answer = app.send(method, &uri, Some(KEY), &[], Body::empty()).await;
        let not_routed =
            answer.status == StatusCode::NOT_FOUND && answer.error().1.starts_with("no route");
        assert!(!not_routed, "{route} is not served");
    }
    assert!(doc["components"]["securitySchemes"]["api_key"].is_object());
    assert!(doc["components"]["schemas"]["SubmitResponse"].is_object());
    let unknown = app.get("/v1/nothing").await;
    assert_eq!(unknown.status, StatusCode::NOT_FOUND);
    assert_eq!(unknown.error().0, "not_found");
    app.finish().await;
}

pub async fn health_readiness_and_metrics_answer(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let health = app
        .send(Method::GET, "/healthz", None, &[], Body::empty())
        .await;
    assert_eq!(health.status, StatusCode::OK);
    let ready = app
        .send(Method::GET, "/readyz", None, &[], Body::empty())
        .await;
    assert_eq!(ready.status, StatusCode::OK);
    assert_eq!(ready.json()["ready"], true);
    app.hooks.redis_down.store(true, Ordering::Relaxed);
    let unready = app
        .send(Method::GET, "/readyz", None, &[], Body::empty())
        .await;
    assert_eq!(unready.status, StatusCode::SERVICE_UNAVAILABLE);
    assert!(unready.headers.contains_key(header::RETRY_AFTER));
    assert_eq!(unready.json()["checks"][1]["name"], "redis");

    let metrics = app
        .send(Method::GET, "/metrics", None, &[], Body::empty())
        .await;
    assert_eq!(metrics.status, StatusCode::OK);
    assert_eq!(
        metrics.headers[header::CONTENT_TYPE],
        "text/plain; version=0.0.4"
    );
    assert_eq!(metrics.body.as_ref(), b"uniphys_up 1\n");
    let traced = app
        .send(
            Method::GET,
            "/healthz",
            None,
            &[(
                "traceparent",
                "00-0af7651916cd43dd8448eb211c80319c-b7ad6b7169203331-01",
            )],
            Body::empty(),
        )
        .await;
    assert_eq!(traced.status, StatusCode::OK);
    let spans = app.hooks.spans.lock().expect("lock").clone();
    assert_eq!(
        spans.last(),
        Some(&(
            "GET".to_owned(),
            "/healthz".to_owned(),
            Some("00-0af7651916cd43dd8448eb211c80319c-b7ad6b7169203331-01".to_owned())
        )),
        "the hooks make each request's span from its route and headers"
    );
    let requests = app.hooks.requests.lock().expect("lock").clone();
    assert!(
        requests.contains(&("GET".into(), "/readyz".into(), 503)),
        "requests are reported with their route: {requests:?}"
    );
    app.finish().await;
}

pub async fn statistics_count_each_stage(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    app.submitted("a.glb", b"a").await;
    app.submitted("b.glb", b"b").await;
    let stats = app.get("/v1/stats").await;
    assert_eq!(stats.status, StatusCode::OK);
    let json = stats.json();
    let stages = json["stages"].as_array().expect("stages");
    let ingest = stages
        .iter()
        .find(|s| s["stage"] == "ingest")
        .expect("ingest");
    assert_eq!(ingest["depth"], 2);
    assert_eq!(ingest["running"], 0);
    let export = stages
        .iter()
        .find(|s| s["stage"] == "export")
        .expect("export");
    assert_eq!(export["blocked"], 2);
    assert_eq!(json["window_secs"], 300);
    let anonymous = app
        .send(Method::GET, "/v1/stats", None, &[], Body::empty())
        .await;
    assert_eq!(anonymous.status, StatusCode::UNAUTHORIZED);
    app.finish().await;
}

pub async fn a_stage_no_worker_takes_is_flagged_unserved(backend: Backend) {
    let window = Duration::from_millis(300);
    let Some(app) = TestApp::open(backend, |c| ApiConfig {
        stats_window: window,
        ..c
    })
    .await
    else {
        return;
    };
    app.submitted("a.glb", b"a").await;
    let unserved = |json: &Value, stage: &str| {
        json["stages"]
            .as_array()
            .expect("stages")
            .iter()
            .find(|s| s["stage"] == stage)
            .unwrap_or_else(|| panic!("{stage} in {json}"))["unserved"]
            .as_bool()
            .expect("unserved is a boolean")
    };
    let fresh = app.get("/v1/stats").await.json();
    assert!(
        !unserved(&fresh, "ingest"),
        "work newer than the window: {fresh}"
    );
    tokio::time::sleep(window + Duration::from_millis(100)).await;
    let stale = app.get("/v1/stats").await.json();
    assert!(
        unserved(&stale, "ingest"),
        "no worker took ingest work: {stale}"
    );
    assert!(
        !unserved(&stale, "export"),
        "blocked work waits for ingest, not a worker"
    );
    app.finish().await;
}

pub async fn an_unreachable_database_is_503_with_retry_after(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    app.store.close().await;
    let answer = app.get("/v1/assets").await;
    assert_eq!(answer.status, StatusCode::SERVICE_UNAVAILABLE);
    assert!(answer.headers.contains_key(header::RETRY_AFTER));
    let (code, message) = answer.error();
    assert_eq!(code, "unavailable");
    assert!(
        !message.contains("pool"),
        "no internals in the answer: {message}"
    );
    let ready = app
        .send(Method::GET, "/readyz", None, &[], Body::empty())
        .await;
    assert_eq!(ready.status, StatusCode::SERVICE_UNAVAILABLE);
    app.finish().await;
}
