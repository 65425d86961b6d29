//! The metric families render with their labels after recording, and the queue gauges follow
//! the store.

use std::time::Duration;

use uniphys_queue::{JobSpec, NewAsset, QueueStore, StageStats, StoreConfig, TableHealth};
use uniphys_telemetry::{Metrics, StageOutcome};

fn assert_has(text: &str, line: &str) {
    assert!(text.contains(line), "missing {line:?} in\n{text}");
}

#[test]
fn recorded_values_appear_with_their_labels() {
    let metrics = Metrics::new();
    metrics.observe_claim_latency("ingest", Duration::from_millis(3));
    metrics.record_stage_attempt(
        "decompose",
        StageOutcome::Succeeded,
        2,
        Duration::from_secs(42),
    );
    metrics.record_stage_attempt(
        "decompose",
        StageOutcome::Retrying,
        1,
        Duration::from_secs(5),
    );
    metrics.record_http_request("POST", "/v1/jobs", 201, Duration::from_millis(12));
    metrics.record_hints_error("publish");
    metrics.record_hints_error("publish");

    let text = metrics.clone().encode();
    assert_has(&text, "# TYPE uniphys_claim_latency_seconds histogram");
    assert_has(
        &text,
        "uniphys_claim_latency_seconds_count{stage=\"ingest\"} 1",
    );
    assert_has(
        &text,
        "uniphys_stage_duration_seconds_bucket{le=\"60.0\",stage=\"decompose\",outcome=\"succeeded\"} 1",
    );
    assert_has(
        &text,
        "uniphys_stage_duration_seconds_bucket{le=\"30.0\",stage=\"decompose\",outcome=\"succeeded\"} 0",
    );
    assert_has(
        &text,
        "uniphys_stage_duration_seconds_bucket{le=\"3600.0\",stage=\"decompose\",outcome=\"retrying\"} 1",
    );
    assert_has(
        &text,
        "uniphys_stage_runs_total{stage=\"decompose\",outcome=\"succeeded\"} 1",
    );
    assert_has(&text, "uniphys_stage_attempts_sum{stage=\"decompose\"} 3.0");
    assert_has(
        &text,
        "uniphys_http_requests_total{method=\"POST\",route=\"/v1/jobs\",status=\"201\"} 1",
    );
    assert_has(
        &text,
        "uniphys_http_request_duration_seconds_count{method=\"POST\",route=\"/v1/jobs\"} 1",
    );
    assert_has(&text, "uniphys_hints_errors_total{op=\"publish\"} 2");
    assert!(text.ends_with("# EOF\n"), "OpenMetrics ends with EOF");
}

#[test]
fn queue_and_table_gauges_render_from_stats() {
    let metrics = Metrics::new();
    let stats = StageStats {
        stage_name: "ingest".to_owned(),
        ready: 3,
        running: 2,
        dead: 1,
        oldest_ready_age_ms: 1500,
        ..StageStats::default()
    };
    let table = TableHealth {
        table: "stage_runs".to_owned(),
        live_rows: 1000,
        dead_rows: 40,
    };
    metrics.set_queue_gauges(&[stats], &[table]);
    let text = metrics.encode();
    for line in [
        "# TYPE uniphys_queue_depth gauge",
        "uniphys_queue_depth{stage=\"ingest\",state=\"ready\"} 3",
        "uniphys_queue_depth{stage=\"ingest\",state=\"running\"} 2",
        "uniphys_queue_depth{stage=\"ingest\",state=\"dead\"} 1",
        "uniphys_queue_depth{stage=\"ingest\",state=\"backing_off\"} 0",
        "# TYPE uniphys_queue_oldest_ready_age_seconds gauge",
        "uniphys_queue_oldest_ready_age_seconds{stage=\"ingest\"} 1.5",
        "uniphys_table_dead_tuples{table=\"stage_runs\"} 40",
        "uniphys_table_live_tuples{table=\"stage_runs\"} 1000",
    ] {
        assert_has(&text, line);
    }
}

#[tokio::test]
async fn refresh_reads_queue_depth_from_the_store() {
    let dir = tempfile::tempdir().expect("temp dir");
    let url = format!("sqlite:{}", dir.path().join("q.db").display());
    let store = QueueStore::open(&StoreConfig::new(url)).expect("open store");
    store.migrate().await.expect("migrate");
    let tenant = store.create_tenant("acme").await.expect("tenant");
    let asset = NewAsset {
        content_digest: "sha256:abc".to_owned(),
        source_uri: "uploads/abc.glb".to_owned(),
        size_bytes: 10,
    };
    store
        .submit(tenant, &asset, &JobSpec::chain(&["ingest", "decompose"]))
        .await
        .expect("submit");

    let metrics = Metrics::new();
    metrics
        .refresh_queue_gauges(&store, Duration::from_secs(60))
        .await
        .expect("refresh");
    let text = metrics.encode();
    assert_has(
        &text,
        "uniphys_queue_depth{stage=\"ingest\",state=\"ready\"} 1",
    );
    assert_has(
        &text,
        "uniphys_queue_depth{stage=\"ingest\",state=\"running\"} 0",
    );
    assert_has(
        &text,
        "uniphys_queue_depth{stage=\"decompose\",state=\"blocked\"} 1",
    );
    assert_has(
        &text,
        "uniphys_queue_depth{stage=\"decompose\",state=\"ready\"} 0",
    );
    assert_has(
        &text,
        "uniphys_queue_oldest_ready_age_seconds{stage=\"ingest\"}",
    );

    // A stage that leaves the statistics loses its series on the next refresh.
    metrics.set_queue_gauges(&[], &[]);
    let text = metrics.encode();
    assert!(
        !text.contains("stage=\"ingest\""),
        "stale series kept:\n{text}"
    );
    store.close().await;
}
