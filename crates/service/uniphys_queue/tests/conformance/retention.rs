//! Retention of finished jobs.

use std::time::Duration;

use uniphys_queue::{Backend, JobSpec, PurgeReport, QueueErrorKind, RetentionPolicy, StageFailure};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn purge_removes_only_jobs_finished_before_the_retention(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest"]);
    let done = t.submit(acme, "done", &spec).await;
    let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    t.complete(&run).await;
    let cancelled = t.submit(acme, "cancelled", &spec).await;
    t.store
        .cancel_job(acme, cancelled.job_id)
        .await
        .expect("cancel");
    let dead = t.submit(acme, "dead", &spec).await;
    let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    t.store
        .fail(&run.lease, &StageFailure::permanent("bad"))
        .await
        .expect("fail");
    let running = t.submit(acme, "running", &spec).await;
    t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    tokio::time::sleep(Duration::from_millis(30)).await;

    let hour = Duration::from_secs(3600);
    let keep_all = RetentionPolicy {
        finished: hour,
        dead: hour,
        batch_size: 1,
    };
    assert_eq!(
        t.store.purge_finished(&keep_all).await.expect("purge"),
        PurgeReport { jobs: 0 }
    );

    let finished_only = RetentionPolicy {
        finished: Duration::ZERO,
        dead: hour,
        batch_size: 1,
    };
    assert_eq!(
        t.store.purge_finished(&finished_only).await.expect("purge"),
        PurgeReport { jobs: 2 }
    );
    for gone in [done.job_id, cancelled.job_id] {
        let err = t.store.get_job(acme, gone).await.expect_err("purged");
        assert_eq!(err.kind(), QueueErrorKind::NotFound);
        assert!(
            t.store
                .job_events(acme, gone)
                .await
                .expect("events")
                .is_empty()
        );
    }
    t.store
        .get_job(acme, dead.job_id)
        .await
        .expect("dead job kept");
    t.store
        .get_job(acme, running.job_id)
        .await
        .expect("running job kept");

    let everything = RetentionPolicy {
        finished: Duration::ZERO,
        dead: Duration::ZERO,
        batch_size: 10,
    };
    assert_eq!(
        t.store.purge_finished(&everything).await.expect("purge"),
        PurgeReport { jobs: 1 }
    );
    t.store
        .get_job(acme, running.job_id)
        .await
        .expect("running job never purged");

    // The asset outlives its jobs: a re-submit de-duplicates and starts a new job.
    let again = t.submit(acme, "done", &spec).await;
    assert_eq!(again.asset_id, done.asset_id);
    assert!(!again.asset_created && again.job_created);
    t.finish().await;
}
