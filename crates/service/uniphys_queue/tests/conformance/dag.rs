//! Completion: output manifests, unblocking dependents in DAG order, finishing the job, atomically.

use std::collections::BTreeSet;

use serde_json::json;
use uniphys_queue::{Backend, JobSpec, JobState, StageCost, StageSpec, StageState};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn completion_unblocks_dependents_in_dag_order(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    // ingest → (ground, colliders) → export
    let spec = JobSpec::new(vec![
        StageSpec::new("ingest"),
        StageSpec::new("ground").after("ingest"),
        StageSpec::new("colliders").after("ingest"),
        StageSpec::new("export").after("ground").after("colliders"),
    ]);
    let sub = t.submit(acme, "a", &spec).await;
    let all = ["ingest", "ground", "colliders", "export"];
    assert_eq!(
        t.claim_names(&all[1..], 10).await.len(),
        0,
        "only ingest is claimable"
    );

    let w = worker("a");
    let ingest = t.claim_one(&w, "ingest", LONG_LEASE).await;
    let manifest = json!({ "mesh": "asset_1/ingest/v1/abc/mesh.bin", "digest": "sha256:abc" });
    let out = t
        .store
        .complete(&ingest.lease, &manifest, &StageCost::default())
        .await
        .expect("complete");
    let names: Vec<&str> = out
        .unblocked
        .iter()
        .map(|r| r.stage_name.as_str())
        .collect();
    assert_eq!(
        names,
        ["colliders", "ground"],
        "by run id: creation order, ties by name"
    );
    assert!(!out.job_succeeded);

    let ground = t.claim_one(&w, "ground", LONG_LEASE).await;
    let inputs = t
        .store
        .upstream_outputs(ground.lease.run_id)
        .await
        .expect("inputs");
    assert_eq!(inputs, [("ingest".to_owned(), manifest.clone())]);
    let out = t
        .store
        .complete(&ground.lease, &json!({"g": 1}), &StageCost::default())
        .await
        .expect("complete");
    assert!(out.unblocked.is_empty(), "export still waits for colliders");
    assert!(t.claim_names(&["export"], 10).await.is_empty());
    assert_eq!(
        t.stage_state(acme, sub.job_id, "export").await,
        StageState::Blocked
    );

    let colliders = t.claim_one(&w, "colliders", LONG_LEASE).await;
    let out = t
        .store
        .complete(&colliders.lease, &json!({"c": 1}), &StageCost::default())
        .await
        .expect("complete");
    assert_eq!(out.unblocked.len(), 1);
    assert_eq!(out.unblocked[0].stage_name, "export");

    let export = t.claim_one(&w, "export", LONG_LEASE).await;
    let inputs = t
        .store
        .upstream_outputs(export.lease.run_id)
        .await
        .expect("inputs");
    assert_eq!(
        inputs,
        [
            ("colliders".to_owned(), json!({"c": 1})),
            ("ground".to_owned(), json!({"g": 1}))
        ]
    );
    let out = t
        .store
        .complete(&export.lease, &json!({"urdf": "x"}), &StageCost::default())
        .await
        .expect("complete");
    assert!(out.job_succeeded);
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Succeeded);
    assert!(
        job.stages
            .iter()
            .all(|s| s.state == StageState::Succeeded && s.finished_at_ms.is_some())
    );
    assert_eq!(
        job.stage("ingest").expect("ingest").output_manifest,
        Some(manifest)
    );
    t.finish().await;
}

pub async fn concurrent_last_completions_finish_the_job_once(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    for round in 0..10 {
        let spec = JobSpec::new(vec![StageSpec::new("left"), StageSpec::new("right")]);
        let sub = t.submit(acme, &format!("pair{round}"), &spec).await;
        let left = t.claim_one(&worker("l"), "left", LONG_LEASE).await;
        let right = t.claim_one(&worker("r"), "right", LONG_LEASE).await;
        let (manifest, cost) = (json!({}), StageCost::default());
        let (a, b) = tokio::join!(
            t.store.complete(&left.lease, &manifest, &cost),
            t.store.complete(&right.lease, &manifest, &cost),
        );
        let finished = [a.expect("left"), b.expect("right")]
            .iter()
            .filter(|o| o.job_succeeded)
            .count();
        assert_eq!(finished, 1, "exactly one completion finishes the job");
        let job = t.store.get_job(acme, sub.job_id).await.expect("job");
        assert_eq!(job.state, JobState::Succeeded);
    }
    t.finish().await;
}

pub async fn fan_in_waits_for_every_parent_under_concurrency(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::new(vec![
        StageSpec::new("a"),
        StageSpec::new("b"),
        StageSpec::new("c"),
        StageSpec::new("join").after("a").after("b").after("c"),
    ]);
    for i in 0..20 {
        t.submit(acme, &format!("j{i}"), &spec).await;
    }
    let mut tasks = Vec::new();
    for w in 0..4 {
        let store = t.store.clone();
        tasks.push(tokio::spawn(async move {
            let mut unblocked = Vec::new();
            loop {
                let runs = store
                    .claim(&worker(&format!("w{w}")), &["a", "b", "c"], LONG_LEASE, 2)
                    .await
                    .expect("claim");
                if runs.is_empty() {
                    return unblocked;
                }
                for run in runs {
                    let out = store
                        .complete(&run.lease, &json!({}), &StageCost::default())
                        .await
                        .expect("complete");
                    unblocked.extend(out.unblocked);
                }
            }
        }));
    }
    let mut unblocked = Vec::new();
    for task in tasks {
        unblocked.extend(task.await.expect("join"));
    }
    assert_eq!(unblocked.len(), 20, "each join unblocked exactly once");
    assert!(unblocked.iter().all(|r| r.stage_name == "join"));
    let ids: BTreeSet<_> = unblocked.iter().map(|r| r.run_id).collect();
    assert_eq!(ids.len(), 20);
    assert_eq!(t.claim_names(&["join"], 100).await.len(), 20);
    t.finish().await;
}
