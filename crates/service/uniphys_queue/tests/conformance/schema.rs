//! Migrations apply, revert and re-apply.

use uniphys_queue::{Backend, JobSpec};

use crate::harness::{self, NO_BACKOFF};

pub async fn migrations_revert_and_reapply(backend: Backend) {
    let Some(t) = harness::open(backend, NO_BACKOFF).await else {
        return;
    };
    let acme = t.tenant("acme").await;
    t.submit(acme, "a", &JobSpec::chain(&["ingest"])).await;
    t.store.migrate().await.expect("migrating twice is a no-op");
    t.store.migrate_down_all().await.expect("revert");
    assert!(
        t.store.create_tenant("after-revert").await.is_err(),
        "tables are gone"
    );
    t.store.migrate().await.expect("re-apply");
    let fresh = t.tenant("acme").await;
    assert_eq!(
        t.claim_names(&["ingest"], 10).await.len(),
        0,
        "re-applied schema starts empty"
    );
    t.submit(fresh, "a", &JobSpec::chain(&["ingest"])).await;
    assert_eq!(t.claim_names(&["ingest"], 10).await, ["ingest"]);
    t.finish().await;
}
