//! A router over a private database (a temp SQLite file, or a fresh Postgres schema) and a
//! temp-directory artifact store, two tenants with keys, and request helpers.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use axum::Router;
use axum::body::{Body, Bytes};
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use serde_json::Value;
use sqlx::Connection;
use tower::ServiceExt;
use uniphys_api::{ApiConfig, ApiState, BoxFuture, MetricsText, ReadinessCheck, ServiceHooks};
use uniphys_queue::{Backend, JobFilter, JobId, JobSpec, QueueStore, StoreConfig, TenantId};
use uniphys_storage::ArtifactStore;

/// The key of the tenant most cases act as.
pub const KEY: &str = "key-of-tenant-one-0123456789";
/// The key of the other tenant.
pub const OTHER_KEY: &str = "key-of-tenant-two-0123456789";

/// The stage graph every submission gets.
pub fn spec() -> JobSpec {
    JobSpec::chain(&["ingest", "export"])
}

/// A router on private stores, with the tenants and what the hooks saw.
pub struct TestApp {
    pub router: Router,
    pub store: QueueStore,
    pub artifacts: ArtifactStore,
    pub tenant: TenantId,
    pub other_tenant: TenantId,
    pub hooks: Arc<RecordingHooks>,
    /// The spool directory of uploads.
    pub spool_dir: std::path::PathBuf,
    cleanup: Cleanup,
    _dirs: tempfile::TempDir,
}

enum Cleanup {
    Sqlite,
    Postgres { url: String, schema: String },
}

/// A response, read whole.
pub struct Answer {
    pub status: StatusCode,
    pub headers: HeaderMap,
    pub body: Bytes,
}

impl Answer {
    /// The body as JSON.
    pub fn json(&self) -> Value {
        serde_json::from_slice(&self.body)
            .unwrap_or_else(|e| panic!("not JSON ({e}): {}", String::from_utf8_lossy(&self.body)))
    }

    /// `error.code` and `error.message` of an error answer.
    pub fn error(&self) -> (String, String) {
        let json = self.json();
        let code = json["error"]["code"]
            .as_str()
            .expect("error.code")
            .to_owned();
        let message = json["error"]["message"]
            .as_str()
            .expect("error.message")
            .to_owned();
        (code, message)
    }
}

impl TestApp {
    /// A migrated store for `backend` with two tenants; `None` when Postgres is not configured.
    pub async fn open(
        backend: Backend,
        configure: impl FnOnce(ApiConfig) -> ApiConfig,
    ) -> Option<Self> {
        let dirs = tempfile::tempdir().expect("temp dir");
        let (config, cleanup) = match backend {
            Backend::Sqlite => {
                let url = format!("sqlite:{}", dirs.path().join("queue.db").display());
                (StoreConfig::new(url), Cleanup::Sqlite)
            }
            Backend::Postgres => {
                let url = postgres_url()?;
                let schema = unique_schema();
                let mut admin = sqlx::PgConnection::connect(&url)
                    .await
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
        let store = QueueStore::connect(&config.with_max_connections(8))
            .await
            .expect("connect");
        store.migrate().await.expect("migrate");
        let tenant = store.create_tenant("one").await.expect("tenant");
        let other_tenant = store.create_tenant("two").await.expect("tenant");
        store.add_api_key(tenant, KEY, "test").await.expect("key");
        store
            .add_api_key(other_tenant, OTHER_KEY, "test")
            .await
            .expect("key");
        let artifacts = ArtifactStore::local(&dirs.path().join("objects")).expect("artifact store");
        let spool_dir = dirs.path().join("spool");
        std::fs::create_dir_all(&spool_dir).expect("spool dir");
        let api_config = configure(ApiConfig::new(spec()).with_upload_tmp_dir(&spool_dir));
        let hooks = Arc::new(RecordingHooks::default());
        let state =
            ApiState::new(store.clone(), artifacts.clone(), api_config).with_hooks(hooks.clone());
        Some(Self {
            router: uniphys_api::router(state),
            store,
            artifacts,
            tenant,
            other_tenant,
            hooks,
            spool_dir,
            cleanup,
            _dirs: dirs,
        })
    }

    /// Closes the store and drops the Postgres schema.
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

    /// Sends a request with an optional bearer key and headers.
    pub async fn send(
        &self,
        method: Method,
        uri: &str,
        key: Option<&str>,
        headers: &[(&str, &str)],
        body: Body,
    ) -> Answer {
        let mut request = Request::builder().method(method).uri(uri);
        if let Some(key) = key {
            request = request.header(header::AUTHORIZATION, format!("Bearer {key}"));
        }
        for (name, value) in headers {
            request = request.header(*name, *value);
        }
        let response = self
            .router
            .clone()
            .oneshot(request.body(body).expect("request"))
            .await
            .expect("infallible");
        let status = response.status();
        let headers = response.headers().clone();
        let body = axum::body::to_bytes(response.into_body(), usize::MAX)
            .await
            .expect("body");
        Answer {
            status,
            headers,
            body,
        }
    }

    /// `GET uri` as the main tenant.
    pub async fn get(&self, uri: &str) -> Answer {
        self.send(Method::GET, uri, Some(KEY), &[], Body::empty())
            .await
    }

    /// `POST uri` with a JSON body as the main tenant.
    pub async fn post_json(&self, uri: &str, body: &str) -> Answer {
        self.send(
            Method::POST,
            uri,
            Some(KEY),
            &[("content-type", "application/json")],
            Body::from(body.to_owned()),
        )
        .await
    }

    /// `POST uri` with no body as the main tenant.
    pub async fn post(&self, uri: &str) -> Answer {
        self.send(Method::POST, uri, Some(KEY), &[], Body::empty())
            .await
    }

    /// Puts `bytes` in the object store at `incoming/t{tenant}/{name}` (where the main tenant
    /// submits by key) and returns the key.
    pub async fn put_incoming(&self, name: &str, bytes: &[u8]) -> String {
        let key = format!("incoming/t{}/{name}", self.tenant.0);
        self.artifacts.put(&key, bytes.to_vec()).await.expect("put");
        key
    }

    /// Uploads `bytes` as `filename` for the main tenant.
    pub async fn upload(&self, filename: &str, bytes: &[u8]) -> Answer {
        self.send(
            Method::POST,
            &format!("/v1/assets?filename={filename}"),
            Some(KEY),
            &[("content-type", "application/octet-stream")],
            Body::from(bytes.to_vec()),
        )
        .await
    }

    /// Uploads `bytes` as `filename` into `batch` for the main tenant, expecting 201; returns
    /// the answer's JSON.
    pub async fn upload_into(&self, filename: &str, bytes: &[u8], batch: &str) -> Value {
        let answer = self
            .send(
                Method::POST,
                &format!("/v1/assets?filename={filename}&batch={batch}"),
                Some(KEY),
                &[("content-type", "application/octet-stream")],
                Body::from(bytes.to_vec()),
            )
            .await;
        assert_eq!(
            answer.status,
            StatusCode::CREATED,
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
        answer.json()
    }

    /// Uploads `bytes` and returns `(asset_id, job_id)`, expecting 201.
    pub async fn submitted(&self, filename: &str, bytes: &[u8]) -> (String, String) {
        let answer = self.upload(filename, bytes).await;
        assert_eq!(
            answer.status,
            StatusCode::CREATED,
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
        let json = answer.json();
        (
            json["asset_id"].as_str().expect("asset_id").to_owned(),
            json["job_id"].as_str().expect("job_id").to_owned(),
        )
    }

    /// Asserts the tenant has no job and the store no source object (a refused submission).
    pub async fn assert_nothing_submitted(&self) {
        let jobs = self
            .store
            .list_jobs(self.tenant, &JobFilter::default())
            .await
            .expect("list");
        assert!(jobs.is_empty(), "no job: {jobs:?}");
        let sources = self.artifacts.list("sources").await.expect("list");
        assert!(sources.is_empty(), "no object: {sources:?}");
    }

    /// Files left in the spool directory.
    pub fn spool_files(&self) -> usize {
        std::fs::read_dir(&self.spool_dir)
            .expect("spool dir")
            .count()
    }
}

/// Parses `job_12` into a [`JobId`].
pub fn job_id(text: &str) -> JobId {
    text.parse().expect("job id")
}

fn postgres_url() -> Option<String> {
    match std::env::var("UNIPHYS_TEST_DATABASE_URL") {
        Ok(url) if !url.is_empty() => Some(url),
        _ if std::env::var_os("CI").is_some() => {
            panic!("CI is set but UNIPHYS_TEST_DATABASE_URL is not: Postgres cases must run in CI")
        }
        _ => {
            eprintln!("skipped: set UNIPHYS_TEST_DATABASE_URL to run the Postgres cases");
            None
        }
    }
}

fn unique_schema() -> String {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    format!(
        "uapi_{}_{}_{nanos}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    )
}

/// Hooks that record doorbells and requests, and answer fixed progress, metrics and readiness.
#[derive(Default)]
pub struct RecordingHooks {
    /// Stage lists passed to `on_stages_ready`, in order.
    pub doorbells: Mutex<Vec<Vec<String>>>,
    /// `(method, route, status)` of each request.
    pub requests: Mutex<Vec<(String, String, u16)>>,
    /// `(method, route, traceparent header)` of each request span asked for.
    pub spans: Mutex<Vec<(String, String, Option<String>)>>,
    /// Whether the required `redis` check fails.
    pub redis_down: std::sync::atomic::AtomicBool,
}

impl ServiceHooks for RecordingHooks {
    fn on_stages_ready<'a>(&'a self, stages: &'a [String]) -> BoxFuture<'a, ()> {
        Box::pin(async move {
            self.doorbells.lock().expect("lock").push(stages.to_vec());
        })
    }

    fn progress(&self, _job: JobId) -> BoxFuture<'_, BTreeMap<String, Value>> {
        Box::pin(async {
            BTreeMap::from([(
                "ingest".to_owned(),
                serde_json::json!({ "done": 1, "total": 4 }),
            )])
        })
    }

    fn metrics_text(&self) -> BoxFuture<'_, Option<MetricsText>> {
        Box::pin(async {
            Some(MetricsText {
                content_type: "text/plain; version=0.0.4".into(),
                body: "uniphys_up 1\n".into(),
            })
        })
    }

    fn current_traceparent(&self) -> Option<String> {
        Some("00-0af7651916cd43dd8448eb211c80319c-b7ad6b7169203331-01".into())
    }

    fn readiness(&self) -> BoxFuture<'_, Vec<ReadinessCheck>> {
        let down = self.redis_down.load(Ordering::Relaxed);
        Box::pin(async move {
            vec![ReadinessCheck {
                name: "redis".into(),
                ok: !down,
                required: true,
            }]
        })
    }

    fn request_span(
        &self,
        method: &axum::http::Method,
        route: &str,
        headers: &HeaderMap,
    ) -> Option<tracing::Span> {
        let traceparent = headers
            .get("traceparent")
            .and_then(|v| v.to_str().ok())
            .map(str::to_owned);
        self.spans
            .lock()
            .expect("lock")
            .push((method.to_string(), route.to_owned(), traceparent));
        None
    }

    fn observe_request(&self, method: &str, route: &str, status: u16, _elapsed: Duration) {
        self.requests
            .lock()
            .expect("lock")
            .push((method.to_owned(), route.to_owned(), status));
    }
}
