//! Listing jobs and table health.

use serde_json::json;
use uniphys_queue::{Backend, JobFilter, JobSpec, JobState, StageCost};

use crate::harness::{self, LONG_LEASE, NO_BACKOFF, worker};

pub async fn listing_filters_and_pages_a_tenants_jobs(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    let other = t.tenant("other").await;
    let spec = JobSpec::chain(&["ingest"]);
    let mut jobs = Vec::new();
    for i in 0..5 {
        jobs.push(t.submit(acme, &format!("a{i}"), &spec).await);
    }
    t.submit(other, "theirs", &spec).await;
    let run = t.claim_one(&worker("a"), "ingest", LONG_LEASE).await;
    t.store
        .complete(&run.lease, &json!({}), &StageCost::default())
        .await
        .expect("complete");

    let all = t
        .store
        .list_jobs(acme, &JobFilter::default())
        .await
        .expect("list");
    let ids: Vec<_> = all.iter().map(|j| j.id).collect();
    let mut want: Vec<_> = jobs.iter().map(|s| s.job_id).collect();
    want.reverse();
    assert_eq!(ids, want, "newest first, only this tenant's");

    let page1 = t
        .store
        .list_jobs(
            acme,
            &JobFilter {
                limit: 2,
                ..JobFilter::default()
            },
        )
        .await
        .expect("page");
    let page2 = t
        .store
        .list_jobs(
            acme,
            &JobFilter {
                limit: 2,
                before: Some(page1[1].id),
                ..JobFilter::default()
            },
        )
        .await
        .expect("page");
    assert_eq!(
        [page1[0].id, page1[1].id, page2[0].id, page2[1].id],
        want[..4]
    );

    let done = t
        .store
        .list_jobs(
            acme,
            &JobFilter {
                state: Some(JobState::Succeeded),
                ..JobFilter::default()
            },
        )
        .await
        .expect("list");
    assert_eq!(done.len(), 1);
    assert_eq!(done[0].id, run.job_id);
    assert!(done[0].finished_at_ms.is_some());
    let of_asset = t
        .store
        .list_jobs(
            acme,
            &JobFilter {
                asset: Some(jobs[2].asset_id),
                ..JobFilter::default()
            },
        )
        .await
        .expect("list");
    assert_eq!(of_asset.len(), 1);
    assert_eq!(of_asset[0].id, jobs[2].job_id);

    // A batch's jobs: only those submitted into it, and only this tenant's.
    let mut in_batch = Vec::new();
    for name in ["b0", "b1"] {
        let sub = t
            .store
            .submit_in_batch(acme, &harness::asset(name), &spec, Some("shelves"))
            .await
            .expect("submit");
        in_batch.push(sub.job_id);
    }
    t.store
        .submit_in_batch(other, &harness::asset("theirs-b"), &spec, Some("shelves"))
        .await
        .expect("submit");
    let batch = |label: &str| JobFilter {
        batch: Some(label.to_owned()),
        ..JobFilter::default()
    };
    let listed = t
        .store
        .list_jobs(acme, &batch("shelves"))
        .await
        .expect("list");
    let ids: Vec<_> = listed.iter().map(|j| j.id).collect();
    in_batch.reverse();
    assert_eq!(ids, in_batch);
    assert!(
        t.store
            .list_jobs(acme, &batch("nothing"))
            .await
            .expect("list")
            .is_empty()
    );
    t.finish().await;
}

pub async fn table_health_reports_the_hot_table(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let health = t.store.table_health().await.expect("health");
    match backend {
        Backend::Sqlite => assert!(health.is_empty()),
        Backend::Postgres => {
            let tables: Vec<&str> = health.iter().map(|h| h.table.as_str()).collect();
            for table in ["events", "jobs", "stage_runs"] {
                assert!(tables.contains(&table), "{tables:?}");
            }
            let mut sorted = tables.clone();
            sorted.sort_unstable();
            assert_eq!(tables, sorted);
        }
    }
    t.finish().await;
}
