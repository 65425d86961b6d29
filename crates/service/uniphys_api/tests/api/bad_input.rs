//! Bad input answers 4xx with a message, and stores nothing.

use axum::body::Body;
use axum::http::{Method, StatusCode, header};
use uniphys_queue::Backend;

use crate::harness::{KEY, OTHER_KEY, TestApp};

pub async fn an_oversize_upload_is_413_and_stores_nothing(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c.with_max_upload_bytes(16)).await else {
        return;
    };
    let big = vec![7u8; 17];
    // Streamed without a length: refused while reading.
    let streamed = app.upload("big.glb", &big).await;
    assert_eq!(streamed.status, StatusCode::PAYLOAD_TOO_LARGE);
    let (code, message) = streamed.error();
    assert_eq!(code, "payload_too_large");
    assert!(message.contains("16 bytes"), "{message}");
    // Declared too large: refused before reading.
    let declared = app
        .send(
            Method::POST,
            "/v1/assets?filename=big.glb",
            Some(KEY),
            &[("content-length", "17")],
            Body::from(big.clone()),
        )
        .await;
    assert_eq!(declared.status, StatusCode::PAYLOAD_TOO_LARGE);

    app.assert_nothing_submitted().await;
    assert_eq!(app.spool_files(), 0, "no spool file");
    assert!(app.hooks.doorbells.lock().expect("lock").is_empty());
    // At the limit is fine.
    assert_eq!(
        app.upload("ok.glb", &big[..16]).await.status,
        StatusCode::CREATED
    );
    app.finish().await;
}

pub async fn a_malformed_manifest_is_400(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    for body in [
        "{not json",
        r#"{"items": "a.glb"}"#,
        r#"{"items": [{"filename": "a.glb"}]}"#,
        r#"{"items": [{"url": 5}]}"#,
        "",
    ] {
        let answer = app.post_json("/v1/batches", body).await;
        assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{body}");
        let (code, message) = answer.error();
        assert_eq!(code, "invalid_json", "{body}");
        assert!(!message.is_empty());
    }
    let missing_url = app
        .post_json("/v1/batches", r#"{"items": [{"filename": "a.glb"}]}"#)
        .await;
    assert!(
        missing_url.error().1.contains("url"),
        "{}",
        missing_url.error().1
    );
    let no_content_type = app
        .send(
            Method::POST,
            "/v1/batches",
            Some(KEY),
            &[],
            Body::from(r#"{"items": []}"#),
        )
        .await;
    assert_eq!(no_content_type.status, StatusCode::BAD_REQUEST);
    assert!(no_content_type.error().1.contains("application/json"));
    app.finish().await;
}

pub async fn unknown_fields_are_400_naming_the_field(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let cases = [
        (
            "/v1/batches",
            r#"{"items": [{"url": "incoming/t1/a.glb", "colour": "red"}]}"#,
            "colour",
        ),
        (
            "/v1/batches",
            r#"{"items": [], "dry_run": true}"#,
            "dry_run",
        ),
        (
            "/v1/assets/by-url",
            r#"{"url": "incoming/t1/a.glb", "prority": 1}"#,
            "prority",
        ),
    ];
    for (uri, body, field) in cases {
        let answer = app.post_json(uri, body).await;
        assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{body}");
        let (_, message) = answer.error();
        assert!(message.contains(field), "{message} should name {field}");
    }
    let query = app.upload("a.glb&colour=red", b"x").await;
    assert_eq!(query.status, StatusCode::BAD_REQUEST);
    assert!(query.error().1.contains("colour"), "{}", query.error().1);
    let list = app.get("/v1/assets?stat=running").await;
    assert_eq!(list.status, StatusCode::BAD_REQUEST);
    assert!(list.error().1.contains("stat"), "{}", list.error().1);
    app.finish().await;
}

pub async fn a_wrong_key_is_401_and_another_tenants_rows_are_404(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let (asset, job) = app.submitted("cabinet.glb", b"mine").await;
    for key in [None, Some("not-a-key-of-anyone-at-all")] {
        let answer = app
            .send(Method::GET, "/v1/assets", key, &[], Body::empty())
            .await;
        assert_eq!(answer.status, StatusCode::UNAUTHORIZED);
        assert_eq!(answer.headers[header::WWW_AUTHENTICATE], "Bearer");
        assert_eq!(answer.error().0, "unauthorized");
    }
    let basic = app
        .send(
            Method::GET,
            "/v1/assets",
            None,
            &[("authorization", "Basic abc")],
            Body::empty(),
        )
        .await;
    assert_eq!(basic.status, StatusCode::UNAUTHORIZED);
    assert!(basic.error().1.contains("Bearer"));
    // An unauthenticated upload is refused before its body is read.
    let upload = app
        .send(
            Method::POST,
            "/v1/assets?filename=x.glb",
            None,
            &[],
            Body::from("x"),
        )
        .await;
    assert_eq!(upload.status, StatusCode::UNAUTHORIZED);

    for (method, uri) in [
        (Method::GET, format!("/v1/assets/{asset}")),
        (Method::GET, format!("/v1/assets/{asset}/artifacts")),
        (
            Method::GET,
            format!("/v1/assets/{asset}/artifacts/ingest/out.json"),
        ),
        (Method::GET, format!("/v1/jobs/{job}")),
        (Method::GET, format!("/v1/jobs/{job}/events")),
        (Method::POST, format!("/v1/jobs/{job}/cancel")),
        (Method::POST, format!("/v1/jobs/{job}/retry")),
    ] {
        let answer = app
            .send(method.clone(), &uri, Some(OTHER_KEY), &[], Body::empty())
            .await;
        assert_eq!(answer.status, StatusCode::NOT_FOUND, "{method} {uri}");
        assert_eq!(answer.error().0, "not_found");
    }
    let theirs = app
        .send(
            Method::GET,
            "/v1/assets",
            Some(OTHER_KEY),
            &[],
            Body::empty(),
        )
        .await;
    assert_eq!(theirs.json()["items"].as_array().map(Vec::len), Some(0));
    // The owner still sees it, and its job is still running.
    assert_eq!(
        app.get(&format!("/v1/jobs/{job}")).await.json()["state"],
        "running"
    );
    app.finish().await;
}

pub async fn invalid_ids_are_400(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    for (method, uri, field) in [
        (Method::GET, "/v1/assets/abc", "asset_id"),
        (Method::GET, "/v1/assets/0", "asset_id"),
        (Method::GET, "/v1/assets/job_3", "asset_id"),
        (Method::GET, "/v1/assets/-4/artifacts", "asset_id"),
        (
            Method::GET,
            "/v1/assets/x/artifacts/ingest/a.json",
            "asset_id",
        ),
        (Method::GET, "/v1/jobs/job_x", "job_id"),
        (Method::GET, "/v1/jobs/1.5/events", "job_id"),
        (
            Method::POST,
            "/v1/jobs/99999999999999999999/cancel",
            "job_id",
        ),
        (Method::POST, "/v1/jobs/asset_1/retry", "job_id"),
        (Method::GET, "/v1/assets?asset=zz", "asset"),
        (Method::GET, "/v1/assets?before=job_0", "before"),
    ] {
        let answer = app
            .send(method.clone(), uri, Some(KEY), &[], Body::empty())
            .await;
        assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{method} {uri}");
        let (code, message) = answer.error();
        assert_eq!(code, "invalid_id", "{uri}");
        assert!(
            message.starts_with(&format!("{field} must be a positive integer")),
            "{uri}: {message}"
        );
    }
    for uri in [
        "/v1/assets?limit=0",
        "/v1/assets?limit=1001",
        "/v1/assets?state=done",
    ] {
        assert_eq!(app.get(uri).await.status, StatusCode::BAD_REQUEST, "{uri}");
    }
    // Well-formed ids that do not exist are 404.
    assert_eq!(
        app.get("/v1/assets/asset_999").await.status,
        StatusCode::NOT_FOUND
    );
    assert_eq!(app.get("/v1/jobs/999").await.status, StatusCode::NOT_FOUND);
    app.finish().await;
}

pub async fn bad_filenames_and_keys_are_422(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let no_ext = app.upload("cabinet", b"x").await;
    assert_eq!(no_ext.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(no_ext.error().1.contains("extension"));
    let no_name = app
        .send(Method::POST, "/v1/assets", Some(KEY), &[], Body::from("x"))
        .await;
    assert_eq!(no_name.status, StatusCode::BAD_REQUEST);
    assert!(
        no_name.error().1.contains("filename"),
        "{}",
        no_name.error().1
    );

    let other = app.other_tenant.0;
    let t = app.tenant.0;
    app.artifacts
        .put(&format!("incoming/t{other}/theirs.glb"), b"theirs".to_vec())
        .await
        .expect("put");
    for (url, expect) in [
        (
            format!("incoming/t{other}/theirs.glb"),
            "must name an object under",
        ),
        (format!("incoming/t{t}/nothing.glb"), "no object at"),
        ("https://example.com/a.glb".to_owned(), "object-store key"),
        (
            format!("incoming/t{t}/../t{other}/theirs.glb"),
            "without . or ..",
        ),
        (
            "1/export/v1/ab/model.urdf".to_owned(),
            "must name an object under",
        ),
    ] {
        let answer = app
            .post_json("/v1/assets/by-url", &format!(r#"{{"url": "{url}"}}"#))
            .await;
        assert_eq!(answer.status, StatusCode::UNPROCESSABLE_ENTITY, "{url}");
        let (_, message) = answer.error();
        assert!(message.contains(expect), "{url}: {message}");
    }
    app.finish().await;
}

pub async fn unsupported_types_and_empty_files_are_refused_at_submission(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let exe = app.upload("setup.exe", b"MZ not a mesh").await;
    assert_eq!(exe.status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    let (code, message) = exe.error();
    assert_eq!(code, "unsupported_media_type");
    assert!(
        message.contains(".exe") && message.contains(".glb") && message.contains(".urdf"),
        "{message}"
    );
    let empty = app.upload("empty.glb", b"").await;
    assert_eq!(empty.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(empty.error().1.contains("empty"), "{}", empty.error().1);
    let declared_empty = app
        .send(
            Method::POST,
            "/v1/assets?filename=empty.glb",
            Some(KEY),
            &[("content-length", "0")],
            Body::empty(),
        )
        .await;
    assert_eq!(declared_empty.status, StatusCode::UNPROCESSABLE_ENTITY);

    let t = app.tenant.0;
    app.artifacts
        .put(&format!("incoming/t{t}/tool.exe"), b"MZ".to_vec())
        .await
        .expect("put");
    app.artifacts
        .put(&format!("incoming/t{t}/nothing.glb"), Vec::new())
        .await
        .expect("put");
    let by_key = |name: &str| format!(r#"{{"url": "incoming/t{t}/{name}"}}"#);
    let exe = app
        .post_json("/v1/assets/by-url", &by_key("tool.exe"))
        .await;
    assert_eq!(exe.status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    let empty = app
        .post_json("/v1/assets/by-url", &by_key("nothing.glb"))
        .await;
    assert_eq!(empty.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(empty.error().1.contains("is empty"), "{}", empty.error().1);

    app.assert_nothing_submitted().await;
    app.finish().await;
}
