//! Status, listing, events, cancel, retry and artifacts, driven through the store like a worker.

use std::time::Duration;

use axum::http::{StatusCode, header};
use sha2::{Digest, Sha256};
use uniphys_queue::{ArtifactEntry, Backend, OutputManifest, StageCost, StageFailure, WorkerId};

use crate::harness::TestApp;

const LEASE: Duration = Duration::from_secs(600);

fn worker() -> WorkerId {
    WorkerId("worker-api-test".into())
}

pub async fn status_shows_each_stage_with_progress(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (asset, job) = app.submitted("cabinet.glb", b"cabinet").await;
    let detail = app.get(&format!("/v1/assets/{asset}")).await;
    assert_eq!(detail.status, StatusCode::OK);
    let json = detail.json();
    assert_eq!(json["asset"]["id"], asset.as_str());
    assert_eq!(json["asset"]["size_bytes"], 7);
    assert_eq!(json["job"]["id"], job.as_str());
    assert_eq!(json["job"]["state"], "running");
    let stages = json["job"]["stages"].as_array().expect("stages");
    let summary: Vec<(&str, &str)> = stages
        .iter()
        .map(|s| {
            (
                s["name"].as_str().expect("name"),
                s["state"].as_str().expect("state"),
            )
        })
        .collect();
    assert_eq!(summary, [("ingest", "ready"), ("export", "blocked")]);
    assert_eq!(stages[0]["max_attempts"], 5);
    assert_eq!(stages[0]["attempt"], 0);
    assert!(
        stages[0]["progress"].is_null() && stages[1]["progress"].is_null(),
        "no progress before a stage runs: {stages:?}"
    );

    // A running stage shows the progress its worker reports.
    let run = &app
        .store
        .claim(&worker(), &["ingest"], LEASE, 1)
        .await
        .expect("claim")[0];
    let running = app.get(&format!("/v1/jobs/{job}")).await.json();
    assert_eq!(running["stages"][0]["state"], "running");
    assert_eq!(
        running["stages"][0]["progress"]["total"], 4,
        "progress comes from the hooks"
    );

    // A failed attempt shows in the stage's errors (and no longer its last progress); the job
    // answers the same by its own id.
    app.store
        .fail(
            &run.lease,
            &StageFailure::transient("model server timed out"),
        )
        .await
        .expect("fail");
    let job_view = app.get(&format!("/v1/jobs/{job}")).await.json();
    assert_eq!(job_view["asset_id"], asset.as_str());
    let ingest = &job_view["stages"][0];
    assert_eq!(ingest["attempt"], 1);
    assert_eq!(ingest["errors"][0]["message"], "model server timed out");
    assert_eq!(ingest["errors"][0]["kind"], "transient");
    assert!(ingest["progress"].is_null(), "{ingest}");

    let events = app.get(&format!("/v1/jobs/{job}/events")).await.json();
    let kinds: Vec<&str> = events["items"]
        .as_array()
        .expect("items")
        .iter()
        .map(|e| e["kind"].as_str().expect("kind"))
        .collect();
    assert_eq!(kinds.first(), Some(&"job_created"));
    assert!(kinds.len() >= 2, "{kinds:?}");
    app.finish().await;
}

pub async fn listing_pages_newest_first_with_a_cursor(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let mut jobs = Vec::new();
    for i in 0..3 {
        jobs.push(
            app.submitted(&format!("a{i}.glb"), format!("asset {i}").as_bytes())
                .await
                .1,
        );
    }
    let first = app.get("/v1/assets?limit=2").await.json();
    let ids: Vec<&str> = first["items"]
        .as_array()
        .expect("items")
        .iter()
        .map(|i| i["job_id"].as_str().expect("job"))
        .collect();
    assert_eq!(ids, [jobs[2].as_str(), jobs[1].as_str()]);
    let next = first["next"].as_str().expect("a next page");
    let second = app
        .get(&format!("/v1/assets?limit=2&before={next}"))
        .await
        .json();
    assert_eq!(second["items"].as_array().map(Vec::len), Some(1));
    assert_eq!(second["items"][0]["job_id"], jobs[0].as_str());
    assert!(second["next"].is_null());

    app.post(&format!("/v1/jobs/{}/cancel", jobs[1])).await;
    let cancelled = app.get("/v1/assets?state=cancelled").await.json();
    assert_eq!(cancelled["items"].as_array().map(Vec::len), Some(1));
    assert_eq!(cancelled["items"][0]["job_id"], jobs[1].as_str());
    let asset0 = second["items"][0]["asset_id"].as_str().expect("asset");
    let by_asset = app.get(&format!("/v1/assets?asset={asset0}")).await.json();
    assert_eq!(by_asset["items"][0]["job_id"], jobs[0].as_str());
    app.finish().await;
}

pub async fn cancelling_a_finished_job_is_409(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (_, job) = app.submitted("cabinet.glb", b"cabinet").await;
    let cancel = app.post(&format!("/v1/jobs/{job}/cancel")).await;
    assert_eq!(cancel.status, StatusCode::OK);
    assert_eq!(cancel.json()["runs_cancelled"], 2);
    let again = app.post(&format!("/v1/jobs/{job}/cancel")).await;
    assert_eq!(again.status, StatusCode::CONFLICT);
    let (code, message) = again.error();
    assert_eq!(code, "conflict");
    assert!(message.contains("cancelled"), "{message}");

    // A succeeded job cannot be cancelled either.
    let (_, done) = app.submitted("done.glb", b"done").await;
    for stage in ["ingest", "export"] {
        let run = &app
            .store
            .claim(&worker(), &[stage], LEASE, 1)
            .await
            .expect("claim")[0];
        app.store
            .complete(
                &run.lease,
                &OutputManifest::default().to_value(),
                &StageCost::default(),
            )
            .await
            .expect("complete");
    }
    let finished = app.post(&format!("/v1/jobs/{done}/cancel")).await;
    assert_eq!(finished.status, StatusCode::CONFLICT);
    assert!(
        finished.error().1.contains("succeeded"),
        "{}",
        finished.error().1
    );
    app.finish().await;
}

pub async fn a_dead_lettered_job_is_retried_and_a_running_one_is_409(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (_, job) = app.submitted("cabinet.glb", b"cabinet").await;
    let running = app.post(&format!("/v1/jobs/{job}/retry")).await;
    assert_eq!(running.status, StatusCode::CONFLICT);
    assert!(
        running.error().1.contains("running"),
        "{}",
        running.error().1
    );

    let run = &app
        .store
        .claim(&worker(), &["ingest"], LEASE, 1)
        .await
        .expect("claim")[0];
    app.store
        .fail(&run.lease, &StageFailure::permanent("not a mesh"))
        .await
        .expect("fail");
    assert_eq!(
        app.get(&format!("/v1/jobs/{job}")).await.json()["state"],
        "dead"
    );
    let retry = app.post(&format!("/v1/jobs/{job}/retry")).await;
    assert_eq!(retry.status, StatusCode::OK);
    assert_eq!(retry.json()["requeued"], serde_json::json!(["ingest"]));
    let view = app.get(&format!("/v1/jobs/{job}")).await.json();
    assert_eq!(view["state"], "running");
    assert_eq!(view["stages"][0]["state"], "ready");
    assert_eq!(
        view["stages"][0]["errors"][0]["message"], "not a mesh",
        "history kept"
    );
    let doorbells = app.hooks.doorbells.lock().expect("lock").clone();
    assert_eq!(
        doorbells.last(),
        Some(&vec!["ingest".to_owned()]),
        "retry rings the doorbell"
    );
    app.finish().await;
}

pub async fn a_cancelled_job_is_offered_on_re_upload_and_retried(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (asset, job) = app.submitted("cabinet.glb", b"cabinet").await;
    let fresh = app.upload("cabinet.glb", b"cabinet").await.json();
    assert_eq!(fresh["job_state"], "running");
    assert!(fresh.get("retry").is_none(), "{fresh}");
    let cancel = app.post(&format!("/v1/jobs/{job}/cancel")).await;
    assert_eq!(cancel.status, StatusCode::OK);

    // The same bytes again, under another name: the cancelled job, and how to run it again.
    let again = app.upload("copy.glb", b"cabinet").await;
    assert_eq!(again.status, StatusCode::OK);
    let again = again.json();
    assert_eq!(again["asset_id"], asset.as_str());
    assert_eq!(again["job_id"], job.as_str());
    assert_eq!(again["job_state"], "cancelled");
    let retry_path = again["retry"].as_str().expect("a retry path").to_owned();
    assert_eq!(retry_path, format!("/v1/jobs/{job}/retry"));

    let retry = app.post(&retry_path).await;
    assert_eq!(retry.status, StatusCode::OK);
    // The first stage runs again; the second waits for it as before.
    assert_eq!(retry.json()["requeued"], serde_json::json!(["ingest"]));
    let view = app.get(&format!("/v1/jobs/{job}")).await.json();
    assert_eq!(view["state"], "running");
    let states: Vec<&str> = view["stages"]
        .as_array()
        .expect("stages")
        .iter()
        .filter_map(|s| s["state"].as_str())
        .collect();
    assert_eq!(states, ["ready", "blocked"]);
    let run = &app
        .store
        .claim(&worker(), &["ingest"], LEASE, 1)
        .await
        .expect("claim")[0];
    assert_eq!(run.job_id.to_string(), job);
    app.finish().await;
}

pub async fn a_completed_stages_artifact_is_listed_and_downloaded(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (asset, job) = app.submitted("cabinet.glb", b"cabinet").await;
    let empty = app
        .get(&format!("/v1/assets/{asset}/artifacts"))
        .await
        .json();
    assert_eq!(empty["job_id"], job.as_str());
    assert_eq!(empty["items"].as_array().map(Vec::len), Some(0));

    let run = &app
        .store
        .claim(&worker(), &["ingest"], LEASE, 1)
        .await
        .expect("claim")[0];
    let content = b"<robot name=\"cabinet\"/>".to_vec();
    let key = format!("{}/ingest/v1/abc/model.urdf", run.asset_id.0);
    app.artifacts.put(&key, content.clone()).await.expect("put");
    let manifest = OutputManifest {
        artifacts: vec![ArtifactEntry {
            name: "urdf/model.urdf".into(),
            key,
            bytes: content.len() as u64,
            sha256: hex::encode(Sha256::digest(&content)),
        }],
        summary: serde_json::json!({ "parts": 3 }),
    };
    app.store
        .complete(&run.lease, &manifest.to_value(), &StageCost::default())
        .await
        .expect("complete");

    let listed = app
        .get(&format!("/v1/assets/{asset}/artifacts"))
        .await
        .json();
    let item = &listed["items"][0];
    assert_eq!(item["path"], "ingest/urdf/model.urdf");
    assert_eq!(item["bytes"], content.len());
    let href = item["href"].as_str().expect("href").to_owned();
    assert_eq!(
        href,
        format!("/v1/assets/{asset}/artifacts/ingest/urdf/model.urdf")
    );
    let status = app.get(&format!("/v1/assets/{asset}")).await.json();
    assert_eq!(status["job"]["stages"][0]["summary"]["parts"], 3);

    let download = app.get(&href).await;
    assert_eq!(download.status, StatusCode::OK);
    assert_eq!(download.body.as_ref(), content.as_slice());
    assert_eq!(download.headers[header::CONTENT_TYPE], "application/xml");
    assert_eq!(
        download.headers[header::CONTENT_LENGTH],
        content.len().to_string().as_str()
    );
    let missing = app
        .get(&format!("/v1/assets/{asset}/artifacts/ingest/other.urdf"))
        .await;
    assert_eq!(missing.status, StatusCode::NOT_FOUND);
    let no_stage = app
        .get(&format!("/v1/assets/{asset}/artifacts/model.urdf"))
        .await;
    assert_eq!(no_stage.status, StatusCode::NOT_FOUND);
    app.finish().await;
}
