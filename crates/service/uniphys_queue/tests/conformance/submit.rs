//! Submitting assets and jobs; tenants and API keys.

use uniphys_queue::{AssetId, Backend, JobSpec, QueueErrorKind, StageSpec, StageState};

use crate::harness::{self, NO_BACKOFF, asset};

pub async fn resubmitting_the_same_content_returns_the_same_asset_and_job(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let other = t.tenant("other").await;
    let spec = JobSpec::chain(&["ingest", "ground", "export"]);

    let first = t.submit(acme, "aaa", &spec).await;
    assert!(first.asset_created && first.job_created);
    let again = t.submit(acme, "aaa", &spec).await;
    assert_eq!(
        (again.asset_id, again.job_id),
        (first.asset_id, first.job_id)
    );
    assert!(!again.asset_created && !again.job_created);

    // Same bytes from another tenant: its own asset and job.
    let theirs = t.submit(other, "aaa", &spec).await;
    assert!(theirs.asset_created);
    assert_ne!(theirs.asset_id, first.asset_id);
    // Re-submits use up no asset id: after three more, new bytes take the next id.
    for _ in 0..3 {
        t.submit(acme, "aaa", &spec).await;
    }
    // Different bytes from the same tenant: a new asset.
    let second = t.submit(acme, "bbb", &spec).await;
    assert_ne!(second.asset_id, first.asset_id);
    assert_eq!(
        second.asset_id.0,
        theirs.asset_id.0 + 1,
        "re-submits used up asset ids"
    );

    let job = t.store.get_job(acme, first.job_id).await.expect("job");
    let names: Vec<&str> = job.stages.iter().map(|s| s.stage_name.as_str()).collect();
    assert_eq!(names, ["ingest", "ground", "export"]);
    let states: Vec<StageState> = job.stages.iter().map(|s| s.state).collect();
    assert_eq!(
        states,
        [StageState::Ready, StageState::Blocked, StageState::Blocked]
    );
    assert_eq!(job.spec, spec);

    // An explicit re-run is a second job on the same asset.
    let rerun = t
        .store
        .create_job(acme, first.asset_id, &spec)
        .await
        .expect("rerun");
    assert_ne!(rerun, first.job_id);
    let latest = t.submit(acme, "aaa", &spec).await;
    assert_eq!(latest.job_id, rerun, "a re-submit returns the latest job");
    t.finish().await;
}

pub async fn concurrent_resubmits_create_one_asset_and_one_job(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest", "export"]);
    let mut tasks = Vec::new();
    for _ in 0..8 {
        let store = t.store.clone();
        let spec = spec.clone();
        tasks.push(tokio::spawn(async move {
            store.submit(acme, &asset("same"), &spec).await
        }));
    }
    let mut results = Vec::new();
    for task in tasks {
        results.push(task.await.expect("join").expect("submit"));
    }
    let created = results.iter().filter(|s| s.asset_created).count();
    assert_eq!(created, 1, "{results:?}");
    assert!(
        results
            .iter()
            .all(|s| s.asset_id == results[0].asset_id && s.job_id == results[0].job_id)
    );
    let runs = t.claim_names(&["ingest"], 100).await;
    assert_eq!(runs, ["ingest"], "exactly one job was created");
    t.finish().await;
}

pub async fn concurrent_capped_submissions_stop_at_the_backlog_cap(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    // Three runs a job and a cap of seven: two jobs fit, a third would make nine.
    let spec = JobSpec::chain(&["ingest", "ground", "export"]);
    let mut tasks = Vec::new();
    for i in 0..8 {
        let store = t.store.clone();
        let spec = spec.clone();
        tasks.push(tokio::spawn(async move {
            store
                .submit_capped(acme, &asset(&format!("c{i}")), &spec, None, Some(7))
                .await
        }));
    }
    let mut accepted = Vec::new();
    for (i, task) in tasks.into_iter().enumerate() {
        match task.await.expect("join") {
            Ok(submission) => accepted.push((i, submission)),
            Err(e) => assert_eq!(e.kind(), QueueErrorKind::Busy, "{e}"),
        }
    }
    assert_eq!(accepted.len(), 2, "{accepted:?}");
    assert_eq!(t.store.tenant_backlog(acme).await.expect("backlog"), 6);
    // Known content makes no job and is never refused.
    let (known, first) = &accepted[0];
    let again = t
        .store
        .submit_capped(acme, &asset(&format!("c{known}")), &spec, None, Some(7))
        .await
        .expect("a re-submit is not refused");
    assert_eq!((again.job_id, again.job_created), (first.job_id, false));
    // Refused submissions kept nothing, not even an asset id: new content takes the next one.
    let late = t.submit(acme, "late", &spec).await;
    let highest = accepted
        .iter()
        .map(|(_, s)| s.asset_id.0)
        .max()
        .expect("ids");
    assert_eq!(late.asset_id.0, highest + 1);
    t.finish().await;
}

pub async fn invalid_or_foreign_submissions_store_nothing(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let other = t.tenant("other").await;

    let cyclic = JobSpec::new(vec![
        StageSpec::new("a").after("b"),
        StageSpec::new("b").after("a"),
    ]);
    let err = t
        .store
        .submit(acme, &asset("x"), &cyclic)
        .await
        .expect_err("cycle");
    assert_eq!(err.kind(), QueueErrorKind::InvalidInput);
    // Nothing was stored: the same digest with a valid spec creates the asset now.
    let ok = t.submit(acme, "x", &JobSpec::chain(&["a"])).await;
    assert!(ok.asset_created);

    let err = t
        .store
        .create_job(other, ok.asset_id, &JobSpec::chain(&["a"]))
        .await
        .expect_err("foreign asset");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);
    let err = t
        .store
        .get_job(other, ok.job_id)
        .await
        .expect_err("foreign job");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);
    let err = t
        .store
        .create_job(acme, AssetId(999_999), &JobSpec::chain(&["a"]))
        .await
        .expect_err("unknown asset");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);
    let err = t
        .store
        .submit(
            uniphys_queue::TenantId(999_999),
            &asset("y"),
            &JobSpec::chain(&["a"]),
        )
        .await
        .expect_err("unknown tenant");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);
    assert_eq!(
        t.claim_names(&["a"], 10).await.len(),
        1,
        "only the valid job exists"
    );
    t.finish().await;
}

pub async fn api_keys_are_stored_hashed_and_resolve_to_their_tenant(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let err = t
        .store
        .create_tenant("acme")
        .await
        .expect_err("duplicate name");
    assert_eq!(err.kind(), QueueErrorKind::Conflict);
    assert_eq!(
        t.store.tenant_by_name("acme").await.expect("lookup"),
        Some(acme)
    );
    assert_eq!(
        t.store.tenant_by_name("nobody").await.expect("lookup"),
        None
    );

    let key = "uk_live_0123456789abcdef0123";
    t.store.add_api_key(acme, key, "ci").await.expect("add key");
    assert_eq!(
        t.store.tenant_for_api_key(key).await.expect("lookup"),
        Some(acme)
    );
    assert_eq!(
        t.store
            .tenant_for_api_key("uk_live_wrong_key_000000")
            .await
            .expect("lookup"),
        None
    );
    let err = t
        .store
        .add_api_key(acme, key, "again")
        .await
        .expect_err("duplicate key");
    assert_eq!(err.kind(), QueueErrorKind::Conflict);
    assert!(t.store.add_api_key(acme, "short", "x").await.is_err());

    assert!(t.store.revoke_api_key(key).await.expect("revoke"));
    assert_eq!(t.store.tenant_for_api_key(key).await.expect("lookup"), None);
    assert!(!t.store.revoke_api_key(key).await.expect("revoke twice"));

    // Rotation: every key of the tenant revoked at once, another tenant's kept.
    let (first, second) = ("uk_live_rotate_first_000000", "uk_live_rotate_second_00000");
    t.store
        .add_api_key(acme, first, "a")
        .await
        .expect("add key");
    t.store
        .add_api_key(acme, second, "b")
        .await
        .expect("add key");
    let other = t.tenant("other").await;
    let theirs = "uk_live_other_tenant_key_000";
    t.store
        .add_api_key(other, theirs, "c")
        .await
        .expect("add key");
    assert_eq!(
        t.store.revoke_tenant_keys(acme).await.expect("revoke all"),
        2
    );
    for key in [first, second] {
        assert_eq!(t.store.tenant_for_api_key(key).await.expect("lookup"), None);
    }
    assert_eq!(
        t.store.tenant_for_api_key(theirs).await.expect("lookup"),
        Some(other)
    );
    t.finish().await;
}

pub async fn tenant_names_are_validated(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let long = "a".repeat(10_000);
    for bad in [
        "",
        "line\nbreak",
        "with space",
        "-lead",
        ".hidden",
        long.as_str(),
    ] {
        let err = t.store.create_tenant(bad).await.expect_err(bad);
        assert_eq!(err.kind(), QueueErrorKind::InvalidInput, "{bad:?}");
        assert!(err.to_string().contains("tenant name"), "{err}");
    }
    for good in ["acme", "lab-3.eu_west", &"b".repeat(64)] {
        t.store.create_tenant(good).await.expect(good);
    }
    t.finish().await;
}
