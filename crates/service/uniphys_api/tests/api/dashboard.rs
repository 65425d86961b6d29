//! What the dashboard reads: the overview (cached statistics, the tenant's jobs, history), the
//! running and dead-lettered work, batches and their dataset statistics, and its static files.

use std::time::Duration;

use axum::body::Body;
use axum::http::{Method, StatusCode, header};
use serde_json::{Value, json};
use uniphys_queue::{Backend, JobSpec, OutputManifest, StageCost, StageFailure, WorkerId};

use crate::harness::{OTHER_KEY, TestApp};

const LEASE: Duration = Duration::from_secs(600);

fn worker() -> WorkerId {
    WorkerId("worker-dashboard-test".into())
}

/// Claims the next run of `stage` and fails it for good with `message`.
async fn dead_letter(app: &TestApp, stage: &str, message: &str) {
    let runs = app
        .store
        .claim(&worker(), &[stage], LEASE, 1)
        .await
        .expect("claim");
    app.store
        .fail(&runs[0].lease, &StageFailure::permanent(message))
        .await
        .expect("fail");
}

/// Claims the next run of `stage` and completes it with `summary`.
async fn complete(app: &TestApp, stage: &str, summary: Value) {
    let runs = app
        .store
        .claim(&worker(), &[stage], LEASE, 1)
        .await
        .expect("claim");
    let manifest = OutputManifest {
        artifacts: Vec::new(),
        summary,
    };
    app.store
        .complete(&runs[0].lease, &manifest.to_value(), &StageCost::default())
        .await
        .expect("complete");
}

pub async fn the_overview_counts_the_tenants_jobs_and_keeps_a_history(backend: Backend) {
    let Some(app) = TestApp::open(backend, |mut c| {
        c.board_refresh = Duration::ZERO;
        c.history_interval = Duration::from_millis(40);
        c
    })
    .await
    else {
        return;
    };
    app.submitted("a.glb", b"a").await;
    app.submitted("b.glb", b"b").await;
    dead_letter(&app, "ingest", "not a mesh").await;
    tokio::time::sleep(Duration::from_millis(300)).await;

    let overview = app.get("/v1/overview").await;
    assert_eq!(overview.status, StatusCode::OK);
    let json = overview.json();
    assert_eq!(json["tenant"]["id"], app.tenant.to_string());
    assert_eq!(json["tenant"]["jobs"]["running"], 1);
    assert_eq!(json["tenant"]["jobs"]["dead"], 1);
    let ingest = json["stages"]
        .as_array()
        .expect("stages")
        .iter()
        .find(|s| s["stage"] == "ingest")
        .expect("ingest")
        .clone();
    assert_eq!(
        (ingest["depth"].as_u64(), ingest["failed"].as_u64()),
        (Some(1), Some(1))
    );

    let samples = json["history"]["samples"]
        .as_array()
        .expect("samples")
        .clone();
    assert!(samples.len() >= 2, "the sampler ran: {samples:?}");
    let times: Vec<i64> = samples
        .iter()
        .map(|s| s["at_ms"].as_i64().expect("at_ms"))
        .collect();
    assert!(
        times.windows(2).all(|w| w[0] < w[1]),
        "oldest first: {times:?}"
    );
    let last = samples.last().expect("a sample");
    let ingest_point = last["stages"]
        .as_array()
        .expect("stages")
        .iter()
        .find(|p| p["stage"] == "ingest")
        .expect("ingest in the sample");
    assert_eq!(ingest_point["failed"], 1);
    let since = times[times.len() - 2];
    let newer = app
        .get(&format!("/v1/overview?since_ms={since}"))
        .await
        .json();
    let newer_times: Vec<i64> = newer["history"]["samples"]
        .as_array()
        .expect("samples")
        .iter()
        .map(|s| s["at_ms"].as_i64().expect("at_ms"))
        .collect();
    assert!(!newer_times.is_empty() && newer_times.iter().all(|t| *t > since));

    let other = app
        .send(
            Method::GET,
            "/v1/overview",
            Some(OTHER_KEY),
            &[],
            Body::empty(),
        )
        .await
        .json();
    assert_eq!(
        other["tenant"]["jobs"]["running"], 0,
        "another tenant's jobs are its own"
    );
    let bad = app.get("/v1/overview?since_ms=yesterday").await;
    assert_eq!(bad.status, StatusCode::BAD_REQUEST);
    app.finish().await;
}

pub async fn the_overview_is_computed_once_per_refresh_for_every_viewer(backend: Backend) {
    let Some(app) = TestApp::open(backend, |mut c| {
        c.board_refresh = Duration::from_secs(3600);
        c.history_interval = Duration::from_secs(3600);
        c
    })
    .await
    else {
        return;
    };
    app.submitted("a.glb", b"a").await;
    let first = app.get("/v1/overview").await.json();
    app.submitted("b.glb", b"b").await;
    let second = app.get("/v1/overview").await.json();
    assert_eq!(
        first["generated_at_ms"], second["generated_at_ms"],
        "within the refresh interval the same statistics are served"
    );
    assert_eq!(first["stages"], second["stages"]);
    assert_ne!(
        ingest_depth(&second),
        Some(2),
        "the second upload is not in the cached statistics"
    );
    let fresh = app.get("/v1/stats").await.json();
    assert_eq!(ingest_depth(&fresh), Some(2), "/v1/stats is always fresh");
    app.finish().await;
}

fn ingest_depth(answer: &Value) -> Option<u64> {
    answer["stages"]
        .as_array()?
        .iter()
        .find(|s| s["stage"] == "ingest")?["depth"]
        .as_u64()
}

pub async fn work_lists_open_stages_and_dead_letters_with_their_errors(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (_, first) = app.submitted("first.glb", b"1").await;
    let (_, second) = app.submitted("second.glb", b"2").await;
    let (_, third) = app.submitted("third.glb", b"3").await;
    // Claims take the oldest first: the first job's ingest is dead-lettered.
    dead_letter(&app, "ingest", "unexpected end of file at byte 1").await;

    let dead = app.get("/v1/work?state=dead").await;
    assert_eq!(dead.status, StatusCode::OK);
    let dead = dead.json();
    let items = dead["items"].as_array().expect("items");
    assert_eq!(
        items.len(),
        2,
        "the dead stage and the stage it blocks: {items:?}"
    );
    assert_eq!(
        (items[1]["stage"].as_str(), items[1]["state"].as_str()),
        (Some("export"), Some("blocked"))
    );
    assert_eq!(items[0]["job_id"], first.as_str());
    assert_eq!(items[0]["file_name"], "first.glb");
    assert_eq!(items[0]["stage"], "ingest");
    assert_eq!(items[0]["state"], "dead");
    assert_eq!(items[0]["errors"], 1);
    assert_eq!(items[0]["last_error"]["kind"], "permanent");
    assert_eq!(
        items[0]["last_error"]["message"],
        "unexpected end of file at byte 1"
    );

    let running = app.get("/v1/work?state=running").await.json();
    let jobs: Vec<&str> = running["items"]
        .as_array()
        .expect("items")
        .iter()
        .map(|i| i["job_id"].as_str().expect("job_id"))
        .collect();
    assert_eq!(
        jobs,
        [third.as_str(), second.as_str()],
        "newest first; blocked stages left out"
    );

    let page = app.get("/v1/work?state=running&limit=1").await.json();
    assert_eq!(page["items"][0]["job_id"], third.as_str());
    assert_eq!(page["next"], third.as_str());
    let rest = app
        .get(&format!("/v1/work?state=running&limit=1&before={third}"))
        .await
        .json();
    assert_eq!(rest["items"][0]["job_id"], second.as_str());

    let others = app
        .send(
            Method::GET,
            "/v1/work?state=dead",
            Some(OTHER_KEY),
            &[],
            Body::empty(),
        )
        .await
        .json();
    assert_eq!(others["items"], json!([]), "another tenant sees none of it");
    for bad in [
        "/v1/work",
        "/v1/work?state=succeeded",
        "/v1/work?state=dead&limit=0",
    ] {
        let answer = app.get(bad).await;
        assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{bad}");
    }
    app.finish().await;
}

fn convert_summary(category: &str, mass_kg: f64, joints: &[(&str, u64)]) -> Value {
    let joint_types: serde_json::Map<String, Value> = joints
        .iter()
        .map(|(k, n)| ((*k).to_owned(), json!(n)))
        .collect();
    json!({
        "passed": true,
        "parts": 3,
        "dataset": {
            "category": category,
            "mass_kg": mass_kg,
            "size_m": [0.5, 0.4, 0.9],
            "materials": {"wood": 2, "metal": 1},
            "joint_types": joint_types,
        }
    })
}

pub async fn a_batch_counts_its_converted_assets(backend: Backend) {
    let Some(app) = TestApp::open(backend, |mut c| {
        c.job_spec = JobSpec::chain(&["ingest", "convert"]);
        c
    })
    .await
    else {
        return;
    };
    app.upload_into("cabinet.glb", b"cabinet", "set-a").await;
    app.upload_into("drawer.glb", b"drawer", "set-a").await;
    app.upload_into("mug.glb", b"mug", "set-b").await;
    app.upload_into("broken.glb", b"broken", "set-a").await;
    for _ in 0..3 {
        complete(&app, "ingest", json!({})).await;
    }
    dead_letter(&app, "ingest", "not a mesh").await;
    complete(
        &app,
        "convert",
        convert_summary("Furniture", 30.0, &[("prismatic", 2), ("fixed", 1)]),
    )
    .await;
    complete(
        &app,
        "convert",
        convert_summary("Furniture", 3.0, &[("revolute", 1)]),
    )
    .await;
    complete(&app, "convert", convert_summary("Kitchenware", 0.3, &[])).await;

    let batches = app.get("/v1/batches").await.json();
    let labels: Vec<(&str, u64)> = batches["items"]
        .as_array()
        .expect("items")
        .iter()
        .map(|b| {
            (
                b["batch"].as_str().expect("batch"),
                b["jobs"].as_u64().expect("jobs"),
            )
        })
        .collect();
    assert_eq!(labels, [("set-b", 1), ("set-a", 3)]);

    let stats = app.get("/v1/batches/set-a/stats").await;
    assert_eq!(stats.status, StatusCode::OK);
    let stats = stats.json();
    assert_eq!(stats["jobs"]["total"], 3);
    assert_eq!(stats["jobs"]["succeeded"], 2);
    assert_eq!(stats["jobs"]["dead"], 1);
    assert_eq!(stats["converted"], 2);
    assert_eq!(
        stats["categories"],
        json!({"Furniture": 2}),
        "set-b's mug is not counted"
    );
    assert_eq!(stats["materials"], json!({"metal": 2, "wood": 4}));
    assert_eq!(
        stats["joint_types"],
        json!({"fixed": 1, "prismatic": 2, "revolute": 1})
    );
    assert_eq!(stats["mass_kg"]["count"], 2);
    assert_eq!(stats["mass_kg"]["max"], 30.0);
    let counts: u64 = stats["mass_kg"]["counts"]
        .as_array()
        .expect("counts")
        .iter()
        .filter_map(Value::as_u64)
        .sum();
    assert_eq!(counts, 2);

    // The same content again into another batch joins the existing job to it.
    let again = app
        .send(
            Method::POST,
            "/v1/assets?filename=cabinet.glb&batch=set-b",
            Some(crate::harness::KEY),
            &[],
            Body::from(&b"cabinet"[..]),
        )
        .await;
    assert_eq!(again.status, StatusCode::OK);
    let set_b = app.get("/v1/batches/set-b/stats").await.json();
    assert_eq!(set_b["jobs"]["total"], 2);
    assert_eq!(set_b["converted"], 2);

    let missing = app.get("/v1/batches/nope/stats").await;
    assert_eq!(missing.status, StatusCode::NOT_FOUND);
    let hidden = app
        .send(
            Method::GET,
            "/v1/batches/set-a/stats",
            Some(OTHER_KEY),
            &[],
            Body::empty(),
        )
        .await;
    assert_eq!(
        hidden.status,
        StatusCode::NOT_FOUND,
        "batches are per tenant"
    );
    let bad = app
        .send(
            Method::POST,
            "/v1/assets?filename=x.glb&batch=two%20words",
            Some(crate::harness::KEY),
            &[],
            Body::from(&b"x"[..]),
        )
        .await;
    assert_eq!(bad.status, StatusCode::BAD_REQUEST);
    assert!(bad.error().1.contains("batch label"), "{}", bad.error().1);
    app.finish().await;
}

pub async fn the_dashboard_is_served_without_a_key(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let root = app.send(Method::GET, "/", None, &[], Body::empty()).await;
    assert_eq!(root.status, StatusCode::PERMANENT_REDIRECT);
    let index = app
        .send(Method::GET, "/ui/", None, &[], Body::empty())
        .await;
    assert_eq!(index.status, StatusCode::OK);
    let html = String::from_utf8_lossy(&index.body);
    assert!(
        html.contains("importmap"),
        "the page maps `three` to the bundled module"
    );
    let three = app
        .send(
            Method::GET,
            "/ui/vendor/three/three.module.js",
            None,
            &[],
            Body::empty(),
        )
        .await;
    assert_eq!(three.status, StatusCode::OK);
    assert_eq!(
        three.headers[header::CONTENT_TYPE],
        "text/javascript; charset=utf-8"
    );
    app.finish().await;
}
