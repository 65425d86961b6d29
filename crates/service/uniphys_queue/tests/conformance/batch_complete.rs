//! Completions in batches: one transaction for many runs, each fenced and answered on its own;
//! the completer that groups concurrent completions.

use std::collections::BTreeSet;

use serde_json::json;
use uniphys_queue::{
    Backend, Completer, Completion, JobSpec, JobState, Lease, MAX_MANIFEST_BYTES, QueueErrorKind,
    StageCost, StageSpec,
};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

fn done(lease: Lease, manifest: serde_json::Value) -> Completion {
    Completion {
        lease,
        output_manifest: manifest,
        cost: StageCost::default(),
    }
}

pub async fn a_batch_completes_each_run_and_fences_the_stale_one(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    // ingest → (ground, colliders) → export, twice.
    let spec = JobSpec::new(vec![
        StageSpec::new("ingest"),
        StageSpec::new("ground").after("ingest"),
        StageSpec::new("colliders").after("ingest"),
        StageSpec::new("export").after("ground").after("colliders"),
    ]);
    let one = t.submit(acme, "one", &spec).await;
    let two = t.submit(acme, "two", &spec).await;
    let w = worker("a");
    let first = t.claim_one(&w, "ingest", LONG_LEASE).await;
    let second = t.claim_one(&w, "ingest", LONG_LEASE).await;
    let stale = Lease {
        attempt: second.lease.attempt + 1,
        ..second.lease
    };
    let huge = json!({ "blob": "x".repeat(MAX_MANIFEST_BYTES) });
    let results = t
        .store
        .complete_many(&[
            done(first.lease, json!({ "mesh": "one" })),
            done(stale, json!({})),
            done(second.lease, huge),
            done(second.lease, json!({ "mesh": "two" })),
        ])
        .await
        .expect("the batch commits");
    assert_eq!(results.len(), 4, "one result per completion, in order");
    let names = |r: &uniphys_queue::CompleteOutcome| {
        r.unblocked
            .iter()
            .map(|u| u.stage_name.clone())
            .collect::<Vec<_>>()
    };
    let ok = results[0].as_ref().expect("first ingest completes");
    assert_eq!(names(ok), ["colliders", "ground"], "by run id");
    let kind = |i: usize| {
        results[i]
            .as_ref()
            .map(|_| ())
            .expect_err("this completion must fail")
            .kind()
    };
    assert_eq!(kind(1), QueueErrorKind::Fenced, "a stale attempt is fenced");
    assert_eq!(
        kind(2),
        QueueErrorKind::InvalidInput,
        "an oversized manifest"
    );
    let ok = results[3].as_ref().expect("second ingest completes");
    assert_eq!(names(ok), ["colliders", "ground"], "by run id");
    let detail = t.store.get_job(acme, two.job_id).await.expect("job");
    assert_eq!(
        detail.stage("ingest").expect("ingest").output_manifest,
        Some(json!({ "mesh": "two" })),
        "the valid completion's manifest was kept"
    );

    // Both parents of job one's export complete in one batch: export is unblocked once, listed
    // under each; then the job's last stage finishes it.
    let ground = t.claim_one(&w, "ground", LONG_LEASE).await;
    let colliders = t.claim_one(&w, "colliders", LONG_LEASE).await;
    assert_eq!((ground.job_id, colliders.job_id), (one.job_id, one.job_id));
    let results = t
        .store
        .complete_many(&[
            done(ground.lease, json!({})),
            done(colliders.lease, json!({})),
        ])
        .await
        .expect("commit");
    for r in &results {
        assert_eq!(names(r.as_ref().expect("completes")), ["export"]);
    }
    assert_eq!(t.claim_names(&["export"], 10).await, ["export"]);
    let events = t.store.job_events(acme, one.job_id).await.expect("events");
    let succeeded = events
        .iter()
        .filter(|e| e.kind == "stage_succeeded")
        .count();
    assert_eq!(succeeded, 3, "ingest, ground and colliders");
    t.finish().await;
}

pub async fn a_job_whose_last_runs_share_a_batch_succeeds_once(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::new(vec![StageSpec::new("left"), StageSpec::new("right")]);
    let sub = t.submit(acme, "pair", &spec).await;
    let w = worker("a");
    let left = t.claim_one(&w, "left", LONG_LEASE).await;
    let right = t.claim_one(&w, "right", LONG_LEASE).await;
    let results = t
        .store
        .complete_many(&[done(left.lease, json!({})), done(right.lease, json!({}))])
        .await
        .expect("commit");
    let finished: Vec<bool> = results
        .iter()
        .map(|r| r.as_ref().expect("completes").job_succeeded)
        .collect();
    assert_eq!(
        finished,
        [false, true],
        "reported on the last of the job's runs"
    );
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Succeeded);
    let events = t.store.job_events(acme, sub.job_id).await.expect("events");
    let kinds: Vec<&str> = events.iter().map(|e| e.kind.as_str()).collect();
    assert_eq!(
        kinds,
        [
            "job_created",
            "stage_succeeded",
            "stage_succeeded",
            "job_succeeded"
        ]
    );
    t.finish().await;
}

pub async fn the_completer_answers_every_concurrent_completion(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["noop"]);
    for i in 0..60 {
        t.submit(acme, &format!("a{i}"), &spec).await;
    }
    let runs = t
        .store
        .claim(&worker("a"), &["noop"], LONG_LEASE, 100)
        .await
        .expect("claim");
    assert_eq!(runs.len(), 60);
    let completer = Completer::spawn(t.store.clone(), 16);
    let mut tasks = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let completer = completer.clone();
        let mut lease = run.lease;
        // Every tenth completion names an attempt that never held the run.
        if i % 10 == 0 {
            lease.attempt += 1;
        }
        tasks.push(tokio::spawn(async move {
            completer
                .complete(&lease, &json!({ "i": i }), &StageCost::default())
                .await
        }));
    }
    let mut fenced = 0;
    let mut completed = BTreeSet::new();
    for (task, run) in tasks.into_iter().zip(&runs) {
        match task.await.expect("join") {
            Ok(outcome) => {
                assert!(outcome.job_succeeded, "a one-stage job ends with its run");
                completed.insert(run.job_id);
            }
            Err(e) => {
                assert_eq!(e.kind(), QueueErrorKind::Fenced, "{e}");
                fenced += 1;
            }
        }
    }
    assert_eq!((completed.len(), fenced), (54, 6));
    for job in &completed {
        let detail = t.store.get_job(acme, *job).await.expect("job");
        assert_eq!(detail.state, JobState::Succeeded);
    }
    t.finish().await;
}
