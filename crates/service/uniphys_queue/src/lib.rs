//! Durable job-queue state for the UniPhys service: tenants and API keys, assets (de-duplicated
//! by content digest per tenant), jobs with their stage graph, stage runs and events, in
//! PostgreSQL (production; claims with `FOR UPDATE SKIP LOCKED`) or SQLite (embedded mode;
//! one writer, `BEGIN IMMEDIATE`), with the same state machine and SQL on both.
//!
//! The contract kept (see `shared/reference/queue-contract.md` §5):
//! - at-least-once: a claim leases a run; a worker renews it with [`QueueStore::heartbeat`];
//!   [`QueueStore::recover_expired_leases`] puts back runs whose worker went silent;
//! - attempts are counted at claim and capped; then the run is dead-lettered with its error history;
//! - every transition of a running run is fenced on its [`Lease`] (run id, attempt): a stale
//!   worker gets [`QueueError::LeaseLost`] and changes nothing;
//! - [`QueueStore::complete`] records the output manifest, unblocks dependent stages and finishes
//!   the job in one transaction; [`QueueStore::complete_many`] does so for many runs with one
//!   statement per step, and a [`Completer`] groups concurrent completions into such batches;
//! - batches label sets of jobs for dataset statistics ([`QueueStore::submit_in_batch`]); the
//!   dashboard's lists ([`QueueStore::list_work`]) read through indexes sized by the page;
//! - all times come from the database clock, in Unix milliseconds (`*_at_ms`).
//!
//! Migrations live in the workspace's `migrations/{postgres,sqlite}/` and are embedded here.

mod completer;
mod config;
mod db;
mod error;
mod ids;
mod manifest;
mod migrations;
mod retry_policy;
mod spec;
mod state;
mod store;

pub use completer::{Completer, DEFAULT_COMPLETION_BATCH};
pub use config::StoreConfig;
pub use error::{QueueError, QueueErrorKind, QueueResult};
pub use ids::{AssetId, JobId, StageRunId, TenantId, WorkerId};
pub use manifest::{ArtifactEntry, OutputManifest};
pub use retry_policy::RetryPolicy;
pub use spec::{DEFAULT_MAX_ATTEMPTS, JobSpec, StageSpec};
pub use state::{JobState, StageState};
pub use store::{
    AssetInfo, Backend, BatchSummary, ClaimedRun, CompleteOutcome, Completion, ErrorRecord,
    FailOutcome, FailureKind, JobDetail, JobEvent, JobFilter, JobSummary, Lease,
    MAX_BATCH_LABEL_CHARS, MAX_MANIFEST_BYTES, MAX_TENANT_NAME_CHARS, NewAsset, PurgeReport,
    QueueStore, RecoveryReport, RetentionPolicy, RunContext, RunRef, StageCost, StageFailure,
    StageRunInfo, StageStats, Submission, TableHealth, WorkItem, oversized_manifest_bytes,
    validate_batch_label, validate_tenant_name,
};
