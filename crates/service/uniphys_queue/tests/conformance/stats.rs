//! Per-stage statistics.

use std::time::Duration;

use serde_json::json;
use uniphys_queue::{Backend, JobSpec, StageCost, StageFailure, StageStats};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn stats_count_each_state_and_the_throughput(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest", "export"]);
    for i in 0..6 {
        t.submit(acme, &format!("a{i}"), &spec).await;
    }
    let w = worker("a");
    // 2 succeeded (unblocking 2 exports), 1 dead, 1 running, 2 ready.
    for _ in 0..2 {
        let run = t.claim_one(&w, "ingest", LONG_LEASE).await;
        t.store
            .complete(&run.lease, &json!({}), &StageCost::default())
            .await
            .expect("complete");
    }
    let run = t.claim_one(&w, "ingest", LONG_LEASE).await;
    t.store
        .fail(&run.lease, &StageFailure::permanent("bad mesh"))
        .await
        .expect("fail");
    t.claim_one(&w, "ingest", LONG_LEASE).await;
    tokio::time::sleep(Duration::from_millis(60)).await;

    let window = Duration::from_secs(10);
    let stats = t.store.stage_stats(window).await.expect("stats");
    let names: Vec<&str> = stats.iter().map(|s| s.stage_name.as_str()).collect();
    assert_eq!(names, ["export", "ingest"], "sorted by stage");
    let ingest = &stats[1];
    let expected = StageStats {
        stage_name: "ingest".into(),
        paused: false,
        blocked: 0,
        ready: 2,
        backing_off: 0,
        running: 1,
        dead: 1,
        succeeded_in_window: 2,
        failed_in_window: 1,
        oldest_ready_age_ms: ingest.oldest_ready_age_ms,
        window,
    };
    assert_eq!(ingest, &expected);
    assert!(
        ingest.oldest_ready_age_ms >= 50,
        "{}",
        ingest.oldest_ready_age_ms
    );
    assert!((ingest.throughput_per_sec() - 0.2).abs() < 1e-9);
    let export = &stats[0];
    assert_eq!((export.blocked, export.ready, export.running), (4, 2, 0));
    t.finish().await;
}
