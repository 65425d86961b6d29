//! A batch exported into the object store as a UniPhys-40K dataset: entity folders, the tables,
//! the summary another API process reads, an export again that copies only what is new, and
//! the bad requests.

use std::time::{Duration, Instant};

use axum::body::Body;
use axum::http::{Method, Request, StatusCode, header};
use serde_json::{Value, json};
use sha2::{Digest, Sha256};
use tower::ServiceExt;
use uniphys_api::{ApiConfig, ApiState};
use uniphys_queue::{
    ArtifactEntry, Backend, JobSpec, OutputManifest, StageCost, StageFailure, WorkerId,
};

use crate::harness::{KEY, OTHER_KEY, TestApp};

const LEASE: Duration = Duration::from_secs(600);

fn worker() -> WorkerId {
    WorkerId("worker-export-test".into())
}

/// Claims the next run of `stage` and completes it with `files` (name, bytes) as its artifacts.
async fn complete_with(app: &TestApp, stage: &str, files: &[(&str, Vec<u8>)]) {
    let run = app
        .store
        .claim(&worker(), &[stage], LEASE, 1)
        .await
        .expect("claim")
        .remove(0);
    let mut artifacts = Vec::new();
    for (name, bytes) in files {
        let key = format!("{}/{stage}/v1/{}/{name}", run.asset_id.0, run.job_id.0);
        app.artifacts.put(&key, bytes.clone()).await.expect("put");
        artifacts.push(ArtifactEntry {
            name: (*name).to_owned(),
            key,
            bytes: bytes.len() as u64,
            sha256: hex::encode(Sha256::digest(bytes)),
        });
    }
    let manifest = OutputManifest {
        artifacts,
        summary: json!({}),
    };
    app.store
        .complete(&run.lease, &manifest.to_value(), &StageCost::default())
        .await
        .expect("complete");
}

/// What a convert stage writes for an object of `category` (the files the export reads, and a
/// model).
fn converted(category: &str, urdf: &str) -> Vec<(&'static str, Vec<u8>)> {
    let json = |v: Value| v.to_string().into_bytes();
    vec![
        (
            "annotations/object.json",
            json(json!({ "category": category })),
        ),
        (
            "record.json",
            json(json!({
                "object": {"category": {"value": category}, "mass_kg": {"value": 2.0}},
                "parts": [{}, {}],
                "joints": [{"kind": "revolute", "provenance": {"kind": "read"}}],
            })),
        ),
        ("report.json", json(json!({ "passed": true }))),
        ("model.urdf", urdf.as_bytes().to_vec()),
    ]
}

/// Polls `GET /v1/batches/{batch}/export` until the export is no longer running.
async fn ended_export(app: &TestApp, batch: &str) -> Value {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let answer = app.get(&format!("/v1/batches/{batch}/export")).await;
        assert_eq!(answer.status, StatusCode::OK);
        let view = answer.json();
        if view["state"] != "running" {
            return view;
        }
        assert!(
            Instant::now() < deadline,
            "the export is still running: {view}"
        );
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

async fn object_text(app: &TestApp, key: &str) -> String {
    String::from_utf8(app.artifacts.get(key).await.expect(key)).expect("utf-8")
}

pub async fn a_batch_is_exported_into_the_store_and_again_adds_only_what_is_new(backend: Backend) {
    let Some(app) = TestApp::open(backend, |mut c| {
        c.job_spec = JobSpec::chain(&["ingest", "convert"]);
        c
    })
    .await
    else {
        return;
    };
    let app_ref = &app;
    let upload = move |name: &'static str, batch: &'static str| async move {
        let json = app_ref.upload_into(name, name.as_bytes(), batch).await;
        let id = |key: &str| json[key].as_str().expect("id").to_owned();
        (id("asset_id"), id("job_id"))
    };
    let (cabinet, cabinet_job) = upload("cabinet.glb", "set-a").await;
    let (drawer, _) = upload("drawer.glb", "set-a").await;
    upload("broken.glb", "set-a").await;
    upload("mug.glb", "set-b").await;
    complete_with(&app, "ingest", &[]).await;
    complete_with(&app, "ingest", &[]).await;
    let broken = app
        .store
        .claim(&worker(), &["ingest"], LEASE, 1)
        .await
        .expect("claim")
        .remove(0);
    app.store
        .fail(&broken.lease, &StageFailure::permanent("not a mesh"))
        .await
        .expect("fail");
    complete_with(
        &app,
        "convert",
        &converted("Furniture/Cabinet", "<robot name='cabinet'/>"),
    )
    .await;

    // The first export: the cabinet is done, the drawer still runs, the broken file is dead.
    let started = app.post("/v1/batches/set-a/export").await;
    assert_eq!(
        started.status,
        StatusCode::ACCEPTED,
        "{}",
        String::from_utf8_lossy(&started.body)
    );
    let prefix = format!("datasets/t{}/set-a/", app.tenant.0);
    assert_eq!(started.json()["prefix"], prefix.as_str());
    let view = ended_export(&app, "set-a").await;
    assert_eq!(view["state"], "finished", "{view}");
    assert_eq!(
        (
            &view["exported"],
            &view["already_there"],
            &view["still_running"],
            &view["failed"]
        ),
        (&json!(1), &json!(0), &json!(1), &json!(1)),
        "{view}"
    );
    let entity = format!("{prefix}Cabinet/cabinet_{cabinet}/");
    assert_eq!(
        object_text(&app, &format!("{entity}model.urdf")).await,
        "<robot name='cabinet'/>"
    );
    let index = object_text(&app, &format!("{prefix}index.csv")).await;
    let lines: Vec<&str> = index.lines().collect();
    assert_eq!(lines.len(), 2, "{index}");
    assert!(lines[0].starts_with("entity,asset_id,job_id,source_file,category,mass_kg"));
    assert!(
        lines[1].starts_with(&format!(
            "Cabinet/cabinet_{cabinet},{cabinet},{cabinet_job},cabinet.glb,Furniture/Cabinet,2.0000,2,1,1,0,0,true,read,0"
        )),
        "{index}"
    );
    let failures = object_text(&app, &format!("{prefix}failures.csv")).await;
    assert!(
        failures
            .lines()
            .nth(1)
            .is_some_and(|l| l.ends_with(",broken.glb,dead,ingest,not a mesh")),
        "{failures}"
    );
    let statistics: Value =
        serde_json::from_str(&object_text(&app, &format!("{prefix}statistics.json")).await)
            .expect("statistics json");
    assert_eq!(statistics["batch"], "set-a");
    assert_eq!(statistics["jobs"]["total"], 3);

    // Once the drawer is done, exporting again copies it alone.
    complete_with(
        &app,
        "convert",
        &converted("Furniture/Drawer", "<robot name='drawer'/>"),
    )
    .await;
    assert_eq!(
        app.post("/v1/batches/set-a/export").await.status,
        StatusCode::ACCEPTED
    );
    let view = ended_export(&app, "set-a").await;
    assert_eq!(
        (
            &view["exported"],
            &view["already_there"],
            &view["still_running"],
            &view["failed"]
        ),
        (&json!(1), &json!(1), &json!(0), &json!(1)),
        "{view}"
    );
    let index = object_text(&app, &format!("{prefix}index.csv")).await;
    assert_eq!(index.lines().count(), 3, "{index}");
    assert!(index.contains(&format!("Drawer/drawer_{drawer},{drawer},")));

    // An asset whose entity holds other bytes (written by something else; of another size, since
    // a file of the listed size is taken as already copied) is listed as a failure with why,
    // and the export goes on.
    let (shelf, _) = upload("shelf.glb", "set-a").await;
    // The mug (set-b) was submitted before the shelf, so its runs are claimed first.
    complete_with(&app, "ingest", &[]).await;
    complete_with(&app, "ingest", &[]).await;
    complete_with(
        &app,
        "convert",
        &converted("Kitchenware/Mug", "<robot name='mug'/>"),
    )
    .await;
    complete_with(
        &app,
        "convert",
        &converted("Furniture/Shelf", "<robot name='shelf'/>"),
    )
    .await;
    app.artifacts
        .put(
            &format!("{prefix}Shelf/shelf_{shelf}/model.urdf"),
            b"<robot name='something else'/>".to_vec(),
        )
        .await
        .expect("put");
    assert_eq!(
        app.post("/v1/batches/set-a/export").await.status,
        StatusCode::ACCEPTED
    );
    let view = ended_export(&app, "set-a").await;
    assert_eq!(view["state"], "finished", "{view}");
    assert_eq!(
        (&view["exported"], &view["already_there"], &view["failed"]),
        (&json!(0), &json!(2), &json!(2)),
        "{view}"
    );
    let failures = object_text(&app, &format!("{prefix}failures.csv")).await;
    assert!(
        failures
            .lines()
            .any(|l| l.contains(",shelf.glb,succeeded,convert,") && l.contains("model.urdf")),
        "{failures}"
    );

    // Another API process (a fresh router on the same stores) answers from the summary.
    let fresh = uniphys_api::router(ApiState::new(
        app.store.clone(),
        app.artifacts.clone(),
        ApiConfig::new(JobSpec::chain(&["ingest", "convert"])),
    ));
    let response = fresh
        .oneshot(
            Request::get("/v1/batches/set-a/export")
                .header(header::AUTHORIZATION, format!("Bearer {KEY}"))
                .body(Body::empty())
                .expect("request"),
        )
        .await
        .expect("infallible");
    assert_eq!(response.status(), StatusCode::OK);
    let body = axum::body::to_bytes(response.into_body(), usize::MAX)
        .await
        .expect("body");
    let summary: Value = serde_json::from_slice(&body).expect("json");
    assert_eq!(summary["state"], "finished");
    assert_eq!(summary["already_there"], 2);

    // Bad requests: a batch never exported, one that does not exist, another tenant's, a
    // malformed label.
    let never = app.get("/v1/batches/set-b/export").await;
    assert_eq!(never.status, StatusCode::NOT_FOUND);
    assert!(never.error().1.contains("POST /v1/batches/set-b/export"));
    assert_eq!(
        app.post("/v1/batches/nothing/export").await.status,
        StatusCode::NOT_FOUND
    );
    let other = app
        .send(
            Method::POST,
            "/v1/batches/set-a/export",
            Some(OTHER_KEY),
            &[],
            Body::empty(),
        )
        .await;
    assert_eq!(other.status, StatusCode::NOT_FOUND);
    assert_eq!(
        app.post("/v1/batches/bad%20label/export").await.status,
        StatusCode::BAD_REQUEST
    );
    app.finish().await;
}
