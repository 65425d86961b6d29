//! [`QueueStore`]: the queue's state and every transition on it, over Postgres or SQLite.
//!
//! Each operation lives in the file named for it. Transactions that touch a job lock its
//! `jobs` row first, then its stage runs, so they cannot deadlock with one another; claims lock
//! only ready runs and skip locked ones.

mod assets;
mod batches;
mod claim;
mod complete;
mod control;
mod events;
mod fail;
mod fencing;
mod health;
mod list;
mod read;
mod release;
mod retention;
mod stats;
mod submit;
mod tenants;
mod work;

use crate::db::{Db, Dialect};
use crate::{QueueResult, RetryPolicy, StoreConfig};

pub use assets::{AssetInfo, RunContext};
pub use batches::{BatchSummary, MAX_BATCH_LABEL_CHARS, validate_batch_label};
pub use claim::{ClaimedRun, Lease};
pub use complete::{
    CompleteOutcome, Completion, MAX_MANIFEST_BYTES, StageCost, oversized_manifest_bytes,
};
pub use control::RunRef;
pub use events::JobEvent;
pub use fail::{ErrorRecord, FailOutcome, FailureKind, RecoveryReport, StageFailure};
pub use health::TableHealth;
pub use list::{JobFilter, JobSummary};
pub use read::{JobDetail, StageRunInfo};
pub use retention::{PurgeReport, RetentionPolicy};
pub use stats::StageStats;
pub use submit::{NewAsset, Submission};
pub use tenants::{MAX_TENANT_NAME_CHARS, validate_tenant_name};
pub use work::WorkItem;

/// Which database a store runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// PostgreSQL: the production store; many processes claim concurrently.
    Postgres,
    /// SQLite: embedded mode; one process, one writer.
    Sqlite,
}

/// The durable queue state. Cheap to clone (pools are shared).
///
/// Time: every timestamp and every lease or backoff comparison uses the database's clock
/// (`*_at_ms` are Unix milliseconds), never a worker's, so clock skew between machines cannot
/// expire or extend a lease.
#[derive(Clone, Debug)]
pub struct QueueStore {
    db: Db,
    retry: RetryPolicy,
}

impl QueueStore {
    /// Opens a store; connections are made on first use, so this does not touch the database.
    pub fn open(config: &StoreConfig) -> QueueResult<Self> {
        Ok(Self {
            db: Db::open(config)?,
            retry: config.retry,
        })
    }

    /// Opens a store and checks that the database answers.
    pub async fn connect(config: &StoreConfig) -> QueueResult<Self> {
        let store = Self::open(config)?;
        store.db.read().await?;
        Ok(store)
    }

    /// Applies the embedded migrations that are not applied yet.
    pub async fn migrate(&self) -> QueueResult<()> {
        let migrator = crate::migrations::migrator(self.db.dialect());
        match &self.db {
            Db::Postgres(pool) => migrator.run(pool).await?,
            Db::Sqlite { writer, .. } => migrator.run(writer).await?,
        }
        Ok(())
    }

    /// Reverts every migration (drops the queue's tables). For tests and operators only.
    pub async fn migrate_down_all(&self) -> QueueResult<()> {
        let migrator = crate::migrations::migrator(self.db.dialect());
        match &self.db {
            Db::Postgres(pool) => migrator.undo(pool, 0).await?,
            Db::Sqlite { writer, .. } => migrator.undo(writer, 0).await?,
        }
        Ok(())
    }

    /// The database this store runs on.
    #[must_use]
    pub fn backend(&self) -> Backend {
        match self.db.dialect() {
            Dialect::Postgres => Backend::Postgres,
            Dialect::Sqlite => Backend::Sqlite,
        }
    }

    /// Closes the pools, waiting for connections in use to be returned.
    pub async fn close(&self) {
        self.db.close().await;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_refuses_unusable_urls() {
        for url in [
            "mysql://x",
            "sqlite::memory:",
            "sqlite:file?mode=memory",
            "",
        ] {
            assert!(QueueStore::open(&StoreConfig::new(url)).is_err(), "{url}");
        }
        let with_schema = StoreConfig::new("sqlite:/tmp/x.db").with_schema("s");
        assert!(
            QueueStore::open(&with_schema).is_err(),
            "a schema is Postgres only"
        );
    }
}
