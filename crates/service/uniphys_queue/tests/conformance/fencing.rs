//! Fencing on (run, attempt), heartbeats and recovery of expired leases.

use std::time::Duration;

use serde_json::json;
use uniphys_queue::{
    Backend, FailureKind, JobSpec, JobState, QueueError, QueueErrorKind, RecoveryReport, StageCost,
    StageFailure, StageSpec, StageState,
};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

const SHORT_LEASE: Duration = Duration::from_millis(200);
/// Comfortably past `SHORT_LEASE`.
const EXPIRE: Duration = Duration::from_millis(450);

pub async fn a_reclaimed_run_rejects_the_stale_worker(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let sub = t
        .submit(acme, "a", &JobSpec::chain(&["ingest", "export"]))
        .await;
    let stale = t.claim_one(&worker("a"), "ingest", SHORT_LEASE).await;
    tokio::time::sleep(EXPIRE).await;
    let report = t.store.recover_expired_leases(100).await.expect("recover");
    assert_eq!(
        report,
        RecoveryReport {
            requeued: 1,
            dead_lettered: 0
        }
    );
    let fresh = t.claim_one(&worker("b"), "ingest", LONG_LEASE).await;
    assert_eq!(fresh.lease.run_id, stale.lease.run_id);
    assert_eq!(fresh.lease.attempt, 2);

    let lost = |r: Result<(), QueueError>| match r {
        Err(QueueError::LeaseLost {
            attempt: 1,
            current_attempt: 2,
            ..
        }) => {}
        other => panic!("expected LeaseLost, got {other:?}"),
    };
    lost(t.store.heartbeat(&stale.lease, LONG_LEASE).await.map(drop));
    lost(
        t.store
            .complete(&stale.lease, &json!({"by": "a"}), &StageCost::default())
            .await
            .map(drop),
    );
    lost(
        t.store
            .fail(&stale.lease, &StageFailure::transient("late"))
            .await
            .map(drop),
    );
    // The stale calls changed nothing: still running under b, export still blocked.
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    let ingest = job.stage("ingest").expect("ingest");
    assert_eq!((ingest.state, ingest.attempt), (StageState::Running, 2));
    assert_eq!(
        ingest.errors.len(),
        1,
        "only the expiry is recorded, not the stale failure"
    );
    assert_eq!(
        job.stage("export").expect("export").state,
        StageState::Blocked
    );

    let done = t
        .store
        .complete(&fresh.lease, &json!({"by": "b"}), &StageCost::default())
        .await
        .expect("complete");
    assert_eq!(done.unblocked.len(), 1);
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(
        job.stage("ingest").expect("ingest").output_manifest,
        Some(json!({"by": "b"}))
    );
    t.finish().await;
}

pub async fn heartbeat_keeps_the_lease_alive(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    let run = t.claim_one(&worker("a"), "ingest", SHORT_LEASE).await;
    let renewed = t
        .store
        .heartbeat(&run.lease, LONG_LEASE)
        .await
        .expect("heartbeat");
    assert!(
        renewed >= run.lease_expires_at_ms + 500_000,
        "renewed to {renewed}"
    );
    tokio::time::sleep(EXPIRE).await;
    let report = t.store.recover_expired_leases(100).await.expect("recover");
    assert_eq!(
        report,
        RecoveryReport::default(),
        "a renewed lease is not recovered"
    );
    t.store
        .complete(&run.lease, &json!({}), &StageCost::default())
        .await
        .expect("complete after renewal");
    t.finish().await;
}

pub async fn completing_twice_is_refused(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let sub = t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    let huge = json!({ "data": "x".repeat(uniphys_queue::MAX_MANIFEST_BYTES) });
    let err = t
        .store
        .complete(&run.lease, &huge, &StageCost::default())
        .await
        .expect_err("huge manifest");
    assert_eq!(err.kind(), QueueErrorKind::InvalidInput);
    let first = t
        .store
        .complete(
            &run.lease,
            &json!({"n": 1}),
            &StageCost {
                gpu_ms: 7,
                ..StageCost::default()
            },
        )
        .await
        .expect("complete");
    assert!(first.job_succeeded);
    let err = t
        .store
        .complete(&run.lease, &json!({"n": 2}), &StageCost::default())
        .await
        .expect_err("second completion");
    assert_eq!(err.kind(), QueueErrorKind::Fenced);
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    let stage = job.stage("ingest").expect("stage");
    assert_eq!(stage.output_manifest, Some(json!({"n": 1})));
    assert_eq!(stage.cost.as_ref().map(|c| c.gpu_ms), Some(7));
    assert_eq!(job.state, JobState::Succeeded);
    t.finish().await;
}

pub async fn expired_leases_are_recovered_with_an_error_record(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let sub = t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    t.submit(acme, "b", &JobSpec::chain(&["ingest"])).await;
    // Long enough that "not expired yet" holds on a loaded machine.
    let dying = t
        .claim_one(&worker("dies"), "ingest", Duration::from_millis(1500))
        .await;
    let healthy = t.claim_one(&worker("lives"), "ingest", LONG_LEASE).await;
    assert_eq!(
        t.store.recover_expired_leases(100).await.expect("recover"),
        RecoveryReport::default(),
        "nothing expired yet"
    );
    tokio::time::sleep(Duration::from_millis(1700)).await;
    let report = t.store.recover_expired_leases(100).await.expect("recover");
    assert_eq!(report.requeued, 1, "only the expired lease is recovered");

    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    let stage = job.stage("ingest").expect("stage");
    assert_eq!(stage.state, StageState::Ready);
    assert_eq!(stage.errors.len(), 1);
    assert_eq!(stage.errors[0].kind, FailureKind::LeaseExpired);
    assert_eq!(stage.errors[0].attempt, 1);
    assert_eq!(stage.errors[0].worker_id.as_deref(), Some("worker-dies"));
    let again = t.claim_one(&worker("c"), "ingest", LONG_LEASE).await;
    assert_eq!(
        (again.lease.run_id, again.lease.attempt),
        (dying.lease.run_id, 2)
    );
    t.store
        .heartbeat(&healthy.lease, LONG_LEASE)
        .await
        .expect("healthy lease untouched");
    t.finish().await;
}

pub async fn a_crash_loop_is_dead_lettered_after_max_attempts(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::new(vec![StageSpec::new("ground").with_max_attempts(2)]);
    let sub = t.submit(acme, "poison", &spec).await;
    let mut reports = Vec::new();
    for attempt in 1..=2 {
        let run = t.claim_one(&worker("oom"), "ground", SHORT_LEASE).await;
        assert_eq!(run.lease.attempt, attempt);
        tokio::time::sleep(EXPIRE).await;
        reports.push(t.store.recover_expired_leases(100).await.expect("recover"));
    }
    assert_eq!(
        reports,
        [
            RecoveryReport {
                requeued: 1,
                dead_lettered: 0
            },
            RecoveryReport {
                requeued: 0,
                dead_lettered: 1
            }
        ]
    );
    assert!(
        t.claim_names(&["ground"], 10).await.is_empty(),
        "a dead run is never claimed"
    );
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Dead);
    let stage = job.stage("ground").expect("stage");
    assert_eq!(stage.state, StageState::Dead);
    let attempts: Vec<u32> = stage.errors.iter().map(|e| e.attempt).collect();
    assert_eq!(attempts, [1, 2]);
    t.finish().await;
}
