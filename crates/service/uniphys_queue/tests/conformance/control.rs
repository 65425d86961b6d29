//! Cancellation and pause/resume.

use serde_json::json;
use uniphys_queue::{
    Backend, JobSpec, JobState, QueueError, QueueErrorKind, StageCost, StageFailure, StageState,
};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn cancel_stops_unfinished_runs_and_fences_the_worker(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let other = t.tenant("other").await;
    let spec = JobSpec::chain(&["ingest", "ground", "export"]);
    let sub = t.submit(acme, "a", &spec).await;
    let keep = t.submit(acme, "b", &spec).await;
    let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    assert_eq!(run.job_id, sub.job_id);

    let err = t
        .store
        .cancel_job(other, sub.job_id)
        .await
        .expect_err("other tenant");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);
    assert_eq!(
        t.store.cancel_job(acme, sub.job_id).await.expect("cancel"),
        3
    );

    assert!(matches!(
        t.store.heartbeat(&run.lease, LONG_LEASE).await,
        Err(QueueError::Cancelled { .. })
    ));
    let err = t
        .store
        .complete(&run.lease, &json!({}), &StageCost::default())
        .await
        .expect_err("complete");
    assert!(matches!(err, QueueError::Cancelled { .. }), "{err}");
    let err = t
        .store
        .fail(&run.lease, &StageFailure::transient("x"))
        .await
        .expect_err("fail");
    assert_eq!(err.kind(), QueueErrorKind::Fenced);

    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Cancelled);
    assert!(job.stages.iter().all(|s| s.state == StageState::Cancelled));
    let err = t
        .store
        .cancel_job(acme, sub.job_id)
        .await
        .expect_err("cancel twice");
    assert!(
        matches!(
            err,
            QueueError::InvalidTransition {
                action: "cancel",
                ..
            }
        ),
        "{err}"
    );

    // The other job is untouched and still runs.
    let next = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    assert_eq!(next.job_id, keep.job_id);
    t.complete(&next).await;
    t.finish().await;
}

pub async fn a_cancelled_job_is_retried_and_its_old_worker_stays_fenced(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest", "ground", "export"]);
    let sub = t.submit(acme, "a", &spec).await;
    let first = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    t.complete(&first).await;
    let stale = t.claim_one(&worker("a"), "ground", LONG_LEASE).await;
    assert_eq!(
        t.store.cancel_job(acme, sub.job_id).await.expect("cancel"),
        2
    );

    let requeued = t.store.retry_job(acme, sub.job_id).await.expect("retry");
    assert_eq!(
        requeued
            .iter()
            .map(|r| r.stage_name.as_str())
            .collect::<Vec<_>>(),
        ["ground"],
        "the stage a cancel stopped runs again; the one after it waits"
    );
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Running);
    assert_eq!(
        t.stage_state(acme, sub.job_id, "ingest").await,
        StageState::Succeeded
    );
    assert_eq!(
        t.stage_state(acme, sub.job_id, "ground").await,
        StageState::Ready
    );
    assert_eq!(
        t.stage_state(acme, sub.job_id, "export").await,
        StageState::Blocked
    );

    // The worker that held the run before the cancel cannot complete it.
    let err = t
        .store
        .complete(&stale.lease, &json!({}), &StageCost::default())
        .await
        .expect_err("stale complete");
    assert_eq!(err.kind(), QueueErrorKind::Fenced, "{err}");
    let fresh = t.claim_one(&worker("b"), "ground", LONG_LEASE).await;
    assert!(fresh.lease.attempt > stale.lease.attempt);
    t.complete(&fresh).await;
    let last = t.claim_one(&worker("b"), "export", LONG_LEASE).await;
    t.complete(&last).await;
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Succeeded);
    t.finish().await;
}

pub async fn pause_holds_claims_until_resume(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    t.submit(acme, "a", &JobSpec::chain(&["ground"])).await;
    t.submit(acme, "b", &JobSpec::chain(&["export"])).await;
    assert!(t.store.pause_stage("ground").await.expect("pause"));
    assert!(!t.store.pause_stage("ground").await.expect("pause twice"));
    assert_eq!(t.store.paused_stages().await.expect("paused"), ["ground"]);

    assert!(t.claim_names(&["ground"], 10).await.is_empty());
    assert_eq!(
        t.claim_names(&["ground", "export"], 10).await,
        ["export"],
        "other stages still run"
    );
    let stats = t
        .store
        .stage_stats(std::time::Duration::from_secs(60))
        .await
        .expect("stats");
    let ground = stats
        .iter()
        .find(|s| s.stage_name == "ground")
        .expect("ground");
    assert!(ground.paused);
    assert_eq!(ground.ready, 1);

    assert!(t.store.resume_stage("ground").await.expect("resume"));
    assert!(!t.store.resume_stage("ground").await.expect("resume twice"));
    assert_eq!(t.claim_names(&["ground"], 10).await, ["ground"]);
    t.finish().await;
}
