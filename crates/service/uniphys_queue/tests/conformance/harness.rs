//! Opens a store on a private database for one case, and the fixtures the cases share.

use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use sqlx::Connection;
use uniphys_queue::{
    Backend, ClaimedRun, JobId, JobSpec, NewAsset, QueueStore, RetryPolicy, StageCost, StoreConfig,
    Submission, TenantId, WorkerId,
};

/// Retries are due at once unless a case asks for a backoff.
pub const NO_BACKOFF: RetryPolicy = RetryPolicy {
    base_delay: Duration::ZERO,
    max_delay: Duration::ZERO,
};

/// A lease no case outlives.
pub const LONG_LEASE: Duration = Duration::from_secs(600);

/// A store on a private database, and how to remove it.
pub struct TestStore {
    pub store: QueueStore,
    cleanup: Cleanup,
}

enum Cleanup {
    Sqlite(
        #[expect(dead_code, reason = "held so the directory lives as long as the store")]
        tempfile::TempDir,
    ),
    Postgres {
        url: String,
        schema: String,
    },
}

/// Opens a migrated store for `backend`; `None` when Postgres is not configured outside CI.
pub async fn open(backend: Backend, retry: RetryPolicy) -> Option<TestStore> {
    let (config, cleanup) = match backend {
        Backend::Sqlite => {
            let dir = tempfile::tempdir().expect("temp dir");
            let url = format!("sqlite:{}", dir.path().join("queue.db").display());
            (StoreConfig::new(url), Cleanup::Sqlite(dir))
        }
        Backend::Postgres => {
            let url = match std::env::var("UNIPHYS_TEST_DATABASE_URL") {
                Ok(url) if !url.is_empty() => url,
                _ if std::env::var_os("CI").is_some() => {
                    panic!(
                        "CI is set but UNIPHYS_TEST_DATABASE_URL is not: Postgres cases must run in CI"
                    )
                }
                _ => {
                    eprintln!("skipped: set UNIPHYS_TEST_DATABASE_URL to run the Postgres cases");
                    return None;
                }
            };
            let schema = unique_schema();
            let mut admin =
                tokio::time::timeout(Duration::from_secs(10), sqlx::PgConnection::connect(&url))
                    .await
                    .unwrap_or_else(|_| panic!("timed out connecting to {url}"))
                    .unwrap_or_else(|e| panic!("cannot connect to {url}: {e}"));
            sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE SCHEMA {schema}")))
                .execute(&mut admin)
                .await
                .expect("create schema");
            admin.close().await.ok();
            (
                StoreConfig::new(url.clone()).with_schema(schema.clone()),
                Cleanup::Postgres { url, schema },
            )
        }
    };
    let store = QueueStore::connect(&config.with_retry(retry).with_max_connections(12))
        .await
        .expect("connect");
    store.migrate().await.expect("migrate");
    Some(TestStore { store, cleanup })
}

fn unique_schema() -> String {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    format!(
        "uq_{}_{}_{nanos}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    )
}

impl TestStore {
    /// Closes the store and drops its database (left in place when the case panicked before).
    pub async fn finish(self) {
        self.store.close().await;
        if let Cleanup::Postgres { url, schema } = self.cleanup {
            let mut admin = sqlx::PgConnection::connect(&url).await.expect("connect");
            sqlx::raw_sql(sqlx::AssertSqlSafe(format!("DROP SCHEMA {schema} CASCADE")))
                .execute(&mut admin)
                .await
                .expect("drop schema");
        }
    }

    /// A new tenant with a unique name.
    pub async fn tenant(&self, name: &str) -> TenantId {
        self.store.create_tenant(name).await.expect("create tenant")
    }

    /// Submits an asset with content `digest` and job `spec`.
    pub async fn submit(&self, tenant: TenantId, digest: &str, spec: &JobSpec) -> Submission {
        self.store
            .submit(tenant, &asset(digest), spec)
            .await
            .expect("submit")
    }

    /// Claims one run of `stage` for `worker`, expecting one.
    pub async fn claim_one(&self, worker: &WorkerId, stage: &str, lease: Duration) -> ClaimedRun {
        let mut runs = self
            .store
            .claim(worker, &[stage], lease, 1)
            .await
            .expect("claim");
        assert_eq!(runs.len(), 1, "expected one claimable {stage} run");
        runs.remove(0)
    }

    /// Completes the held `run` with an empty manifest, expecting it to be accepted.
    pub async fn complete(&self, run: &ClaimedRun) {
        self.store
            .complete(&run.lease, &serde_json::json!({}), &StageCost::default())
            .await
            .unwrap_or_else(|e| panic!("complete {}: {e}", run.stage_name));
    }

    /// Claims up to `limit` runs of `stages`, returning their stage names in claim order.
    pub async fn claim_names(&self, stages: &[&str], limit: u32) -> Vec<String> {
        let runs = self
            .store
            .claim(&worker("probe"), stages, LONG_LEASE, limit)
            .await
            .expect("claim");
        runs.into_iter().map(|r| r.stage_name).collect()
    }

    /// The state of `stage` in `job`.
    pub async fn stage_state(
        &self,
        tenant: TenantId,
        job: JobId,
        stage: &str,
    ) -> uniphys_queue::StageState {
        let detail = self.store.get_job(tenant, job).await.expect("get job");
        detail.stage(stage).expect("stage exists").state
    }
}

pub fn asset(digest: &str) -> NewAsset {
    NewAsset {
        content_digest: format!("sha256:{digest}"),
        source_uri: format!("uploads/{digest}.glb"),
        size_bytes: 1234,
    }
}

pub fn worker(name: &str) -> WorkerId {
    WorkerId(format!("worker-{name}"))
}
