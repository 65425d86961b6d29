//! Claims: exclusivity under concurrency, attempts and leases, order, stage selection.

use std::collections::BTreeSet;
use std::time::Duration;

use uniphys_queue::{Backend, JobSpec, StageCost, StageState};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn concurrent_claimers_get_each_run_exactly_once(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest"]);
    for i in 0..200 {
        t.submit(acme, &format!("asset{i}"), &spec).await;
    }
    let mut tasks = Vec::new();
    for w in 0..8_u32 {
        let store = t.store.clone();
        tasks.push(tokio::spawn(async move {
            let me = worker(&format!("w{w}"));
            let mut mine = Vec::new();
            loop {
                let runs = store
                    .claim(&me, &["ingest"], LONG_LEASE, 1 + w % 3)
                    .await
                    .expect("claim");
                if runs.is_empty() {
                    return mine;
                }
                for run in runs {
                    assert_eq!(run.lease.attempt, 1);
                    store
                        .complete(
                            &run.lease,
                            &serde_json::json!({ "by": w }),
                            &StageCost::default(),
                        )
                        .await
                        .expect("complete own claim");
                    mine.push(run.lease.run_id);
                }
            }
        }));
    }
    let mut all = Vec::new();
    let mut busy_workers = 0;
    for task in tasks {
        let mine = task.await.expect("join");
        busy_workers += usize::from(!mine.is_empty());
        all.extend(mine);
    }
    let distinct: BTreeSet<_> = all.iter().collect();
    assert_eq!(all.len(), 200, "every run claimed once");
    assert_eq!(distinct.len(), 200, "no run claimed twice");
    assert!(busy_workers >= 2, "claims were spread over workers");
    let stats = t
        .store
        .stage_stats(Duration::from_secs(3600))
        .await
        .expect("stats");
    assert_eq!(
        (
            stats[0].ready,
            stats[0].running,
            stats[0].succeeded_in_window
        ),
        (0, 0, 200)
    );
    t.finish().await;
}

pub async fn claim_counts_the_attempt_and_sets_the_lease(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let sub = t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    let before = t
        .store
        .get_job(acme, sub.job_id)
        .await
        .expect("job")
        .created_at_ms;
    let run = t
        .claim_one(&worker("a"), "ingest", Duration::from_secs(30))
        .await;
    assert_eq!(
        (run.job_id, run.tenant_id, run.asset_id),
        (sub.job_id, acme, sub.asset_id)
    );
    assert_eq!((run.lease.attempt, run.max_attempts), (1, 5));
    let lease_ms = run.lease_expires_at_ms - before;
    assert!(
        (29_000..=35_000).contains(&lease_ms),
        "lease of {lease_ms} ms"
    );

    let info = t.store.get_job(acme, sub.job_id).await.expect("job");
    let stage = info.stage("ingest").expect("stage");
    assert_eq!(stage.state, StageState::Running);
    assert_eq!(
        stage.worker_id.as_ref().map(|w| w.0.as_str()),
        Some("worker-a")
    );
    assert_eq!(stage.lease_expires_at_ms, Some(run.lease_expires_at_ms));
    assert!(stage.started_at_ms.is_some());
    assert!(
        t.claim_names(&["ingest"], 10).await.is_empty(),
        "a running run is not claimable"
    );
    t.finish().await;
}

pub async fn claims_follow_priority_then_age(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let mut expected = Vec::new();
    for (digest, priority) in [
        ("low1", 0),
        ("high1", 10),
        ("low2", 0),
        ("mid", 5),
        ("high2", 10),
    ] {
        let spec = JobSpec::chain(&["ingest"]).with_priority(priority);
        let sub = t.submit(acme, digest, &spec).await;
        expected.push((priority, sub.job_id, digest));
        // Distinct ages even on a coarse clock.
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    expected.sort_by_key(|(p, job, _)| (std::cmp::Reverse(*p), *job));
    let mut order = Vec::new();
    for _ in 0..5 {
        let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
        order.push(run.job_id);
    }
    let want: Vec<_> = expected.iter().map(|(_, job, _)| *job).collect();
    assert_eq!(order, want, "high1, high2, mid, low1, low2");

    // A batch claim returns the same order.
    for (digest, priority) in [("b1", 1), ("b2", 3), ("b3", 2)] {
        t.submit(
            acme,
            digest,
            &JobSpec::chain(&["export"]).with_priority(priority),
        )
        .await;
    }
    let batch = t
        .store
        .claim(&worker("b"), &["export"], LONG_LEASE, 10)
        .await
        .expect("claim");
    let priorities: Vec<_> = batch.iter().map(|r| r.job_id).collect();
    assert_eq!(priorities.len(), 3);
    let details = [
        t.store
            .get_job(acme, priorities[0])
            .await
            .expect("job")
            .priority,
        t.store
            .get_job(acme, priorities[1])
            .await
            .expect("job")
            .priority,
        t.store
            .get_job(acme, priorities[2])
            .await
            .expect("job")
            .priority,
    ];
    assert_eq!(details, [3, 2, 1]);
    t.finish().await;
}

pub async fn claims_only_take_the_named_stages(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    t.submit(acme, "b", &JobSpec::chain(&["decompose"])).await;
    t.submit(acme, "c", &JobSpec::chain(&["verify"])).await;
    assert!(t.claim_names(&[], 10).await.is_empty());
    assert!(t.claim_names(&["export"], 10).await.is_empty());
    let mut got = t.claim_names(&["verify", "ingest"], 10).await;
    got.sort();
    assert_eq!(got, ["ingest", "verify"]);
    assert_eq!(
        t.claim_names(&["ingest", "decompose", "verify"], 10).await,
        ["decompose"]
    );
    t.finish().await;
}

pub async fn a_recovered_run_is_claimed_before_newer_work(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest"]);
    let old = t.submit(acme, "old", &spec).await;
    let dying = t
        .claim_one(&worker("dies"), "ingest", Duration::from_millis(300))
        .await;
    assert_eq!(dying.job_id, old.job_id);
    // Work submitted after the old job, waiting while the old run's worker dies.
    let newer = t.submit(acme, "newer", &spec).await;
    tokio::time::sleep(Duration::from_millis(500)).await;
    let report = t.store.recover_expired_leases(10).await.expect("recover");
    assert_eq!(report.requeued, 1);
    let order: Vec<_> = [
        t.claim_one(&worker("a"), "ingest", LONG_LEASE).await.job_id,
        t.claim_one(&worker("a"), "ingest", LONG_LEASE).await.job_id,
    ]
    .into();
    assert_eq!(
        order,
        [old.job_id, newer.job_id],
        "the rescued run goes first, not behind work that became ready before it was put back"
    );
    t.finish().await;
}
