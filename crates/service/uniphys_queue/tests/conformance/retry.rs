//! Failures: backoff, dead-lettering with the error history, retrying dead jobs.

use std::time::Duration;

use serde_json::json;
use uniphys_queue::{
    Backend, FailOutcome, FailureKind, JobSpec, JobState, QueueErrorKind, RetryPolicy, StageCost,
    StageFailure, StageSpec, StageState,
};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn transient_failures_wait_for_their_backoff(backend: Backend) {
    let policy = RetryPolicy {
        base_delay: Duration::from_millis(1600),
        max_delay: Duration::from_secs(10),
    };
    let Some(t) = harness::open(backend, policy).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let sub = t.submit(acme, "a", &JobSpec::chain(&["ground"])).await;
    let run = t.claim_one(&worker("a"), "ground", LONG_LEASE).await;
    let outcome = t
        .store
        .fail(&run.lease, &StageFailure::transient("lvlm 503"))
        .await
        .expect("fail");
    let FailOutcome::RetryScheduled { run_after_ms } = outcome else {
        panic!("expected a retry, got {outcome:?}")
    };
    let errors = &t.store.get_job(acme, sub.job_id).await.expect("job").stages[0].errors;
    let delay_ms = run_after_ms - errors[0].at_ms;
    assert!(
        (800..=1600).contains(&delay_ms),
        "first backoff is 800..1600 ms with jitter, got {delay_ms}"
    );

    assert!(
        t.claim_names(&["ground"], 1).await.is_empty(),
        "not claimable during the backoff"
    );
    let stats = t
        .store
        .stage_stats(Duration::from_secs(60))
        .await
        .expect("stats");
    assert_eq!(
        (
            stats[0].ready,
            stats[0].backing_off,
            stats[0].failed_in_window
        ),
        (0, 1, 1)
    );
    tokio::time::sleep(Duration::from_millis(1700)).await;
    let again = t.claim_one(&worker("b"), "ground", LONG_LEASE).await;
    assert_eq!(again.lease.attempt, 2);
    t.finish().await;
}

pub async fn exhausted_attempts_dead_letter_with_the_error_history(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::new(vec![
        StageSpec::new("ground").with_max_attempts(3),
        StageSpec::new("export").after("ground"),
    ]);
    let sub = t.submit(acme, "a", &spec).await;
    let mut outcomes = Vec::new();
    for n in 1..=3 {
        let run = t.claim_one(&worker("a"), "ground", LONG_LEASE).await;
        let failure = StageFailure::transient(format!("timeout {n}"));
        outcomes.push(t.store.fail(&run.lease, &failure).await.expect("fail"));
    }
    assert!(matches!(outcomes[0], FailOutcome::RetryScheduled { .. }));
    assert!(matches!(outcomes[1], FailOutcome::RetryScheduled { .. }));
    assert_eq!(outcomes[2], FailOutcome::DeadLettered);

    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Dead);
    assert!(job.finished_at_ms.is_some());
    let ground = job.stage("ground").expect("ground");
    assert_eq!(ground.state, StageState::Dead);
    let history: Vec<(u32, &str)> = ground
        .errors
        .iter()
        .map(|e| (e.attempt, e.message.as_str()))
        .collect();
    assert_eq!(
        history,
        [(1, "timeout 1"), (2, "timeout 2"), (3, "timeout 3")]
    );
    assert!(
        ground
            .errors
            .iter()
            .all(|e| e.kind == FailureKind::Transient)
    );
    assert_eq!(
        job.stage("export").expect("export").state,
        StageState::Blocked
    );

    let kinds: Vec<String> = t
        .store
        .job_events(acme, sub.job_id)
        .await
        .expect("events")
        .into_iter()
        .map(|e| e.kind)
        .collect();
    assert_eq!(
        kinds,
        [
            "job_created",
            "stage_failed",
            "stage_failed",
            "stage_dead",
            "job_dead"
        ]
    );
    let stats = t
        .store
        .stage_stats(Duration::from_secs(60))
        .await
        .expect("stats");
    let ground_stats = stats
        .iter()
        .find(|s| s.stage_name == "ground")
        .expect("ground stats");
    assert_eq!((ground_stats.dead, ground_stats.failed_in_window), (1, 3));
    t.finish().await;
}

pub async fn permanent_failures_dead_letter_at_once(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let sub = t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    let outcome = t
        .store
        .fail(
            &run.lease,
            &StageFailure::permanent("not a mesh: 0 triangles"),
        )
        .await
        .expect("fail");
    assert_eq!(outcome, FailOutcome::DeadLettered);
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Dead);
    let stage = job.stage("ingest").expect("stage");
    assert_eq!((stage.attempt, stage.errors.len()), (1, 1));
    assert_eq!(stage.errors[0].kind, FailureKind::Permanent);
    t.finish().await;
}

pub async fn retrying_a_dead_job_grants_a_fresh_budget_and_keeps_history(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let other = t.tenant("other").await;
    let spec = JobSpec::new(vec![
        StageSpec::new("ground").with_max_attempts(2),
        StageSpec::new("export").after("ground"),
    ]);
    let sub = t.submit(acme, "a", &spec).await;
    let err = t
        .store
        .retry_job(acme, sub.job_id)
        .await
        .expect_err("running job");
    assert_eq!(err.kind(), QueueErrorKind::Conflict);
    for _ in 0..2 {
        let run = t.claim_one(&worker("a"), "ground", LONG_LEASE).await;
        t.store
            .fail(&run.lease, &StageFailure::transient("boom"))
            .await
            .expect("fail");
    }
    assert_eq!(
        t.stage_state(acme, sub.job_id, "ground").await,
        StageState::Dead
    );
    let err = t
        .store
        .retry_job(other, sub.job_id)
        .await
        .expect_err("other tenant");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);

    let requeued = t.store.retry_job(acme, sub.job_id).await.expect("retry");
    assert_eq!(requeued.len(), 1);
    assert_eq!(requeued[0].stage_name, "ground");
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Running);
    let ground = job.stage("ground").expect("ground");
    assert_eq!(
        (ground.state, ground.max_attempts, ground.errors.len()),
        (StageState::Ready, 4, 2)
    );

    // The attempt counter keeps counting: it is the fencing token.
    let run = t.claim_one(&worker("b"), "ground", LONG_LEASE).await;
    assert_eq!(run.lease.attempt, 3);
    t.store
        .complete(&run.lease, &json!({}), &StageCost::default())
        .await
        .expect("complete");
    let export = t.claim_one(&worker("b"), "export", LONG_LEASE).await;
    let done = t
        .store
        .complete(&export.lease, &json!({}), &StageCost::default())
        .await
        .expect("complete");
    assert!(done.job_succeeded);
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.state, JobState::Succeeded);
    assert_eq!(
        job.stage("ground").expect("ground").errors.len(),
        2,
        "history survives success"
    );
    t.finish().await;
}
