//! What workers and the API read besides jobs: assets, a tenant's backlog, a run's context, and
//! releasing a held run on shutdown.

use serde_json::json;
use uniphys_queue::{
    Backend, JobSpec, OutputManifest, QueueError, QueueErrorKind, StageCost, StageState,
};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, asset, worker};

pub async fn assets_and_backlog_are_per_tenant(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let other = t.tenant("other").await;
    let spec = JobSpec::chain(&["ingest", "export"]);
    let sub = t.submit(acme, "a", &spec).await;
    t.submit(acme, "b", &spec).await;

    let info = t.store.get_asset(acme, sub.asset_id).await.expect("asset");
    assert_eq!(info.id, sub.asset_id);
    assert_eq!(info.tenant_id, acme);
    assert_eq!(info.content_digest, asset("a").content_digest);
    assert_eq!(info.source_uri, asset("a").source_uri);
    assert_eq!(info.size_bytes, asset("a").size_bytes);
    let err = t
        .store
        .get_asset(other, sub.asset_id)
        .await
        .expect_err("another tenant's asset");
    assert_eq!(err.kind(), QueueErrorKind::NotFound);

    assert_eq!(t.store.tenant_backlog(acme).await.expect("backlog"), 4);
    assert_eq!(t.store.tenant_backlog(other).await.expect("backlog"), 0);
    let run = t.claim_one(&worker("w"), "ingest", LONG_LEASE).await;
    t.store
        .complete(&run.lease, &json!({}), &StageCost::default())
        .await
        .expect("complete");
    assert_eq!(t.store.tenant_backlog(acme).await.expect("backlog"), 3);
    t.finish().await;
}

pub async fn run_context_carries_the_asset_trace_and_upstream(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let trace = "00-0af7651916cd43dd8448eb211c80319c-b7ad6b7169203331-01";
    let spec = JobSpec::chain(&["ingest", "export"]).with_trace_parent(Some(trace.into()));
    let sub = t.submit(acme, "a", &spec).await;
    let first = t.claim_one(&worker("w"), "ingest", LONG_LEASE).await;
    let manifest = OutputManifest {
        artifacts: vec![],
        summary: json!({ "parts": 4 }),
    };
    t.store
        .complete(&first.lease, &manifest.to_value(), &StageCost::default())
        .await
        .expect("complete");
    let second = t.claim_one(&worker("w"), "export", LONG_LEASE).await;
    let ctx = t
        .store
        .run_context(second.lease.run_id)
        .await
        .expect("context");
    assert_eq!(ctx.job_id, sub.job_id);
    assert_eq!(ctx.asset.id, sub.asset_id);
    assert_eq!(ctx.trace_parent.as_deref(), Some(trace));
    assert_eq!(ctx.upstream.len(), 1);
    assert_eq!(ctx.upstream[0].0, "ingest");
    assert_eq!(
        OutputManifest::from_value(&ctx.upstream[0].1),
        Some(manifest)
    );
    let bad = JobSpec::chain(&["x"]).with_trace_parent(Some("a\nb".into()));
    let err = t
        .store
        .submit(acme, &asset("bad"), &bad)
        .await
        .expect_err("control characters in trace_parent");
    assert_eq!(err.kind(), QueueErrorKind::InvalidInput);
    t.finish().await;
}

pub async fn a_released_run_is_claimable_at_once_without_using_an_attempt(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let spec = JobSpec::chain(&["ingest"]);
    let sub = t.submit(acme, "a", &spec).await;
    let first = t.claim_one(&worker("old"), "ingest", LONG_LEASE).await;
    t.store.release(&first.lease).await.expect("release");
    let err = t
        .store
        .release(&first.lease)
        .await
        .expect_err("release twice");
    assert!(matches!(err, QueueError::LeaseLost { .. }), "{err}");

    let second = t.claim_one(&worker("new"), "ingest", LONG_LEASE).await;
    assert_eq!(second.lease.run_id, first.lease.run_id);
    assert_eq!(second.lease.attempt, first.lease.attempt + 1);
    assert_eq!(second.max_attempts, first.max_attempts + 1);
    let err = t
        .store
        .complete(&first.lease, &json!({}), &StageCost::default())
        .await
        .expect_err("the releasing worker is fenced");
    assert_eq!(err.kind(), QueueErrorKind::Fenced);
    t.store
        .complete(&second.lease, &json!({}), &StageCost::default())
        .await
        .expect("complete");
    let job = t.store.get_job(acme, sub.job_id).await.expect("job");
    assert_eq!(job.stages[0].state, StageState::Succeeded);
    let kinds: Vec<String> = t
        .store
        .job_events(acme, sub.job_id)
        .await
        .expect("events")
        .into_iter()
        .map(|e| e.kind)
        .collect();
    assert!(kinds.iter().any(|k| k == "stage_released"), "{kinds:?}");
    t.finish().await;
}
