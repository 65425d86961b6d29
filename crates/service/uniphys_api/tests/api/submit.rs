//! Submitting: upload, by key, batches, idempotent re-submits, the backlog cap.

use axum::http::{StatusCode, header};
use sha2::{Digest, Sha256};
use uniphys_queue::{Backend, JobFilter};

use crate::harness::{TestApp, job_id};

pub async fn an_upload_creates_an_asset_and_the_same_bytes_return_the_same_ids(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let bytes = b"glTF binary pretending to be a cabinet";
    let first = app.upload("cabinet.glb", bytes).await;
    assert_eq!(first.status, StatusCode::CREATED);
    let json = first.json();
    let digest = hex::encode(Sha256::digest(bytes));
    assert_eq!(json["content_digest"], format!("sha256:{digest}"));
    assert_eq!(json["created"], true);
    assert_eq!(json["size_bytes"], bytes.len());
    let key = format!("sources/t{}/{digest}/cabinet.glb", app.tenant.0);
    assert_eq!(json["source_key"], key.as_str());
    assert_eq!(app.artifacts.get(&key).await.expect("stored"), bytes);
    let asset_id = json["asset_id"].as_str().expect("asset id");
    assert_eq!(
        first.headers[header::LOCATION],
        format!("/v1/assets/{asset_id}").as_str()
    );
    assert_eq!(
        *app.hooks.doorbells.lock().expect("lock"),
        vec![vec!["ingest".to_owned()]],
        "the first stage's doorbell rang once"
    );
    let job = app
        .store
        .get_job(app.tenant, job_id(json["job_id"].as_str().expect("job")))
        .await
        .expect("job");
    assert_eq!(
        job.spec.trace_parent.as_deref(),
        Some("00-0af7651916cd43dd8448eb211c80319c-b7ad6b7169203331-01"),
        "the job carries the request's trace context"
    );

    let again = app.upload("cabinet.glb", bytes).await;
    assert_eq!(again.status, StatusCode::OK);
    let again = again.json();
    assert_eq!(again["asset_id"], json["asset_id"]);
    assert_eq!(again["job_id"], json["job_id"]);
    assert_eq!(again["created"], false);
    assert_eq!(
        app.hooks.doorbells.lock().expect("lock").len(),
        1,
        "no new job, no doorbell"
    );
    let jobs = app
        .store
        .list_jobs(app.tenant, &JobFilter::default())
        .await
        .expect("list");
    assert_eq!(jobs.len(), 1);

    // The same bytes under other names: the same asset, its own key, and no second copy.
    for name in ["copy.glb", "another.glb"] {
        let renamed = app.upload(name, bytes).await;
        assert_eq!(renamed.status, StatusCode::OK, "{name}");
        let renamed = renamed.json();
        assert_eq!(renamed["asset_id"], json["asset_id"]);
        assert_eq!(renamed["source_key"], key.as_str(), "{name}");
    }
    let stored = app.artifacts.list("sources").await.expect("list");
    assert_eq!(stored, vec![key.clone()], "one object per content");
    assert_eq!(app.spool_files(), 0, "spool files are removed");
    app.finish().await;
}

pub async fn an_object_in_the_store_is_submitted_by_key(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let incoming = format!("incoming/t{}/drawer.obj", app.tenant.0);
    app.artifacts
        .put(&incoming, b"v 0 0 0\n".to_vec())
        .await
        .expect("put");
    let body = format!(r#"{{"url": "{incoming}", "priority": 5}}"#);
    let answer = app.post_json("/v1/assets/by-url", &body).await;
    assert_eq!(
        answer.status,
        StatusCode::CREATED,
        "{}",
        String::from_utf8_lossy(&answer.body)
    );
    let json = answer.json();
    let digest = hex::encode(Sha256::digest(b"v 0 0 0\n"));
    assert_eq!(json["content_digest"], format!("sha256:{digest}"));
    let key = format!("sources/t{}/{digest}/drawer.obj", app.tenant.0);
    assert_eq!(json["source_key"], key.as_str());
    assert_eq!(app.artifacts.get(&key).await.expect("copied"), b"v 0 0 0\n");
    let job = app
        .store
        .get_job(app.tenant, job_id(json["job_id"].as_str().expect("job")))
        .await
        .expect("job");
    assert_eq!(job.priority, 5);

    let again = app.post_json("/v1/assets/by-url", &body).await;
    assert_eq!(again.status, StatusCode::OK);
    assert_eq!(again.json()["asset_id"], json["asset_id"]);
    app.finish().await;
}

pub async fn a_batch_is_validated_whole_before_anything_is_submitted(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let t = app.tenant.0;
    for name in ["a.glb", "b.glb"] {
        app.put_incoming(name, name.as_bytes()).await;
    }
    let bad = format!(
        r#"{{"items": [{{"url": "incoming/t{t}/a.glb"}}, {{"url": "incoming/t{t}/missing.glb"}}, {{"url": "incoming/t{t}/b.glb", "filename": "noext"}}]}}"#
    );
    let answer = app.post_json("/v1/batches", &bad).await;
    assert_eq!(answer.status, StatusCode::UNPROCESSABLE_ENTITY);
    let (_, message) = answer.error();
    assert!(
        message.contains("items[1]") && message.contains("missing.glb"),
        "{message}"
    );
    assert!(
        message.contains("items[2]") && message.contains("extension"),
        "{message}"
    );
    assert!(!message.contains("items[0]"), "{message}");
    let jobs = app
        .store
        .list_jobs(app.tenant, &JobFilter::default())
        .await
        .expect("list");
    assert!(jobs.is_empty(), "nothing was submitted");

    let good = format!(
        r#"{{"items": [{{"url": "incoming/t{t}/a.glb"}}, {{"url": "incoming/t{t}/b.glb", "filename": "bee.glb", "priority": 2}}, {{"url": "incoming/t{t}/a.glb"}}]}}"#
    );
    let answer = app.post_json("/v1/batches", &good).await;
    assert_eq!(
        answer.status,
        StatusCode::OK,
        "{}",
        String::from_utf8_lossy(&answer.body)
    );
    let items = answer.json()["items"].as_array().expect("items").clone();
    let statuses: Vec<u64> = items
        .iter()
        .map(|i| i["status"].as_u64().expect("status"))
        .collect();
    // Items are submitted concurrently: one of the two copies of a.glb creates the asset.
    assert_eq!(statuses[1], 201);
    let mut repeated = [statuses[0], statuses[2]];
    repeated.sort_unstable();
    assert_eq!(repeated, [200, 201], "the repeated item is a re-submit");
    assert_eq!(
        items[0]["submission"]["asset_id"],
        items[2]["submission"]["asset_id"]
    );
    assert!(
        items[1]["submission"]["source_key"]
            .as_str()
            .expect("key")
            .ends_with("/bee.glb")
    );

    let empty = app.post_json("/v1/batches", r#"{"items": []}"#).await;
    assert_eq!(empty.status, StatusCode::UNPROCESSABLE_ENTITY);
    app.finish().await;
}

pub async fn a_full_backlog_answers_429_with_retry_after(backend: Backend) {
    // Two stages per job: a cap of 3 admits one job, not two.
    let Some(app) = TestApp::open(backend, |c| c.with_max_backlog_per_tenant(3)).await else {
        return;
    };
    app.submitted("one.glb", b"one").await;
    let answer = app.upload("two.glb", b"two").await;
    assert_eq!(answer.status, StatusCode::TOO_MANY_REQUESTS);
    assert_eq!(answer.headers[header::RETRY_AFTER], "30");
    let (code, message) = answer.error();
    assert_eq!(code, "backlog_full");
    assert!(message.contains("cap 3"), "{message}");
    let other = app
        .send(
            axum::http::Method::POST,
            "/v1/assets?filename=two.glb",
            Some(crate::harness::OTHER_KEY),
            &[],
            axum::body::Body::from("two"),
        )
        .await;
    assert_eq!(other.status, StatusCode::CREATED, "the cap is per tenant");
    app.finish().await;
}

pub async fn concurrent_uploads_never_take_the_tenant_over_its_cap_together(backend: Backend) {
    // Two stages per job: a cap of 7 admits three jobs. Uploads far from the cap go on the
    // API's estimate; the ones near it are counted in their transactions.
    let Some(app) = TestApp::open(backend, |c| c.with_max_backlog_per_tenant(7)).await else {
        return;
    };
    let bodies: Vec<String> = (0..12).map(|i| format!("asset {i}")).collect();
    let app_ref = &app;
    let answers =
        futures::future::join_all(bodies.iter().enumerate().map(|(i, body)| async move {
            app_ref.upload(&format!("a{i}.glb"), body.as_bytes()).await
        }))
        .await;
    let created = answers
        .iter()
        .filter(|a| a.status == StatusCode::CREATED)
        .count();
    assert!(
        answers
            .iter()
            .all(|a| a.status == StatusCode::CREATED || a.status == StatusCode::TOO_MANY_REQUESTS),
        "every upload is taken or told to wait"
    );
    // Never over the cap; a request racing others near it may be told to wait early.
    assert!((1..=3).contains(&created), "{created} jobs made");
    assert_eq!(
        app.store.tenant_backlog(app.tenant).await.expect("backlog"),
        2 * created as u64
    );
    // One at a time, the rest of the room is taken, and no more.
    let mut made = created;
    for i in 0..4 {
        let answer = app
            .upload(&format!("b{i}.glb"), format!("more {i}").as_bytes())
            .await;
        if answer.status == StatusCode::CREATED {
            made += 1;
        } else {
            assert_eq!(answer.status, StatusCode::TOO_MANY_REQUESTS);
        }
    }
    assert_eq!(made, 3);
    assert_eq!(
        app.store.tenant_backlog(app.tenant).await.expect("backlog"),
        6
    );
    app.finish().await;
}

pub async fn a_partial_batch_submits_the_valid_items_and_refuses_each_bad_one(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let t = app.tenant.0;
    for name in ["a.glb", "b.glb"] {
        app.put_incoming(name, name.as_bytes()).await;
    }
    let manifest = format!(
        r#"{{"all_or_nothing": false, "batch": "chunk", "items": [{{"url": "incoming/t{t}/a.glb"}}, {{"url": "incoming/t{t}/missing.glb"}}, {{"url": "incoming/t{t}/b.glb"}}, {{"url": "incoming/t{t}/b.glb", "filename": "noext"}}]}}"#
    );
    let statuses = |answer: &crate::harness::Answer| -> Vec<u64> {
        answer.json()["items"]
            .as_array()
            .expect("items")
            .iter()
            .map(|i| i["status"].as_u64().expect("status"))
            .collect()
    };
    let first = app.post_json("/v1/batches", &manifest).await;
    assert_eq!(first.status, StatusCode::OK, "{}", first.error().1);
    assert_eq!(statuses(&first), [201, 422, 201, 422], "in manifest order");
    let items = first.json()["items"].clone();
    assert!(
        items[1]["error"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("missing.glb")),
        "{items}"
    );
    // Sent again, the known items are the same jobs and nothing new is made.
    let again = app.post_json("/v1/batches", &manifest).await;
    assert_eq!(statuses(&again), [200, 422, 200, 422]);
    assert_eq!(
        again.json()["items"][0]["submission"]["job_id"],
        items[0]["submission"]["job_id"]
    );
    let jobs = app
        .store
        .list_jobs(app.tenant, &JobFilter::default())
        .await
        .expect("list");
    assert_eq!(jobs.len(), 2);
    app.finish().await;
}
