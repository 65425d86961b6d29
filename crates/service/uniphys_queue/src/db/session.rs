//! Pools and sessions. Postgres: one pool; writers run concurrently and claim with
//! `FOR UPDATE SKIP LOCKED`. SQLite (embedded mode): one writer connection, so writes are
//! serialized in-process, and every write transaction starts with `BEGIN IMMEDIATE`, so a second
//! process on the same file waits for the write lock instead of failing halfway; readers use a
//! separate pool and see the last commit (WAL).

use std::str::FromStr;
use std::time::Duration;

use sqlx::pool::PoolConnection;
use sqlx::postgres::{PgConnectOptions, PgPoolOptions};
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{PgConnection, PgPool, Postgres, Sqlite, SqliteConnection, SqlitePool, Transaction};

use super::bind::{bind_pg, bind_sqlite};
use super::{Arg, DbRow, Dialect, Sql};
use crate::{QueueError, QueueResult, StoreConfig};

/// The connection pools of one store.
#[derive(Clone, Debug)]
pub(crate) enum Db {
    Postgres(PgPool),
    Sqlite {
        writer: SqlitePool,
        readers: SqlitePool,
    },
}

/// A transaction, or one connection for single autocommit statements.
pub(crate) enum Session {
    PgTx(Transaction<'static, Postgres>),
    PgAuto(PoolConnection<Postgres>),
    SqliteTx(Transaction<'static, Sqlite>),
    SqliteAuto(PoolConnection<Sqlite>),
}

enum Conn<'a> {
    Pg(&'a mut PgConnection),
    Sqlite(&'a mut SqliteConnection),
}

/// Creates the SQLite file at `path` readable and writable by its owner only (0600), or makes
/// an existing one of ours so; a folder that does not exist is left for SQLite to report.
fn private_database_file(path: &std::path::Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
        if path
            .parent()
            .is_some_and(|d| !d.as_os_str().is_empty() && !d.is_dir())
        {
            return Ok(());
        }
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(0o600)
            .open(path)
        {
            Ok(_) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                // Best effort on a file made by an older version: another owner's file is
                // opened as it is.
                let _ = std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o600));
                Ok(())
            }
            Err(e) => Err(e),
        }
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        Ok(())
    }
}

impl Db {
    /// Opens the pools for `config.url` (`postgres://…` or `sqlite:…`); connects lazily.
    pub(crate) fn open(config: &StoreConfig) -> QueueResult<Self> {
        let url = config.url.as_str();
        if url.starts_with("postgres://") || url.starts_with("postgresql://") {
            // A session stuck inside a transaction (a frozen process) loses it after a minute,
            // releasing its row locks; queue transactions last milliseconds.
            let mut options = PgConnectOptions::from_str(url)?
                .options([("idle_in_transaction_session_timeout", "60000")]);
            if let Some(schema) = &config.schema {
                options = options.options([("search_path", schema.as_str())]);
            }
            let pool = PgPoolOptions::new()
                .max_connections(config.max_connections)
                .acquire_timeout(config.acquire_timeout)
                .connect_lazy_with(options);
            Ok(Self::Postgres(pool))
        } else if url.starts_with("sqlite:") {
            if url.contains(":memory:") || url.contains("mode=memory") {
                // The writer and the readers are separate connections: they must share a file.
                return Err(QueueError::Invalid(
                    "SQLite needs a file, not :memory:".into(),
                ));
            }
            if config.schema.is_some() {
                return Err(QueueError::Invalid(
                    "a schema applies to Postgres only".into(),
                ));
            }
            let options = SqliteConnectOptions::from_str(url)?;
            // Only this user reads the queue (API key digests, tenants' files by name); SQLite
            // gives its journal files the database file's mode.
            private_database_file(options.get_filename()).map_err(|e| {
                QueueError::Invalid(format!(
                    "cannot create the database file {}: {e}",
                    options.get_filename().display()
                ))
            })?;
            let options = options
                .create_if_missing(true)
                .journal_mode(SqliteJournalMode::Wal)
                .synchronous(SqliteSynchronous::Normal)
                .foreign_keys(true)
                .busy_timeout(Duration::from_secs(30));
            let writer = SqlitePoolOptions::new()
                .max_connections(1)
                .acquire_timeout(config.acquire_timeout)
                .connect_lazy_with(options.clone());
            let readers = SqlitePoolOptions::new()
                .max_connections(config.max_connections)
                .acquire_timeout(config.acquire_timeout)
                .connect_lazy_with(options);
            Ok(Self::Sqlite { writer, readers })
        } else {
            Err(QueueError::Invalid(format!(
                "database url must start with postgres:// or sqlite:, got {url:?}"
            )))
        }
    }

    pub(crate) fn dialect(&self) -> Dialect {
        match self {
            Self::Postgres(_) => Dialect::Postgres,
            Self::Sqlite { .. } => Dialect::Sqlite,
        }
    }

    /// Starts a write transaction (SQLite: `BEGIN IMMEDIATE`, taking the write lock now).
    pub(crate) async fn write_tx(&self) -> QueueResult<Session> {
        Ok(match self {
            Self::Postgres(pool) => Session::PgTx(pool.begin().await?),
            Self::Sqlite { writer, .. } => {
                Session::SqliteTx(writer.begin_with("BEGIN IMMEDIATE").await?)
            }
        })
    }

    /// A session for one write statement in autocommit mode (atomic on its own).
    pub(crate) async fn write_one(&self) -> QueueResult<Session> {
        Ok(match self {
            Self::Postgres(pool) => Session::PgAuto(pool.acquire().await?),
            Self::Sqlite { writer, .. } => Session::SqliteAuto(writer.acquire().await?),
        })
    }

    /// A session for reads; each statement sees the last commit.
    pub(crate) async fn read(&self) -> QueueResult<Session> {
        Ok(match self {
            Self::Postgres(pool) => Session::PgAuto(pool.acquire().await?),
            Self::Sqlite { readers, .. } => Session::SqliteAuto(readers.acquire().await?),
        })
    }

    pub(crate) async fn close(&self) {
        match self {
            Self::Postgres(pool) => pool.close().await,
            Self::Sqlite { writer, readers } => {
                readers.close().await;
                writer.close().await;
            }
        }
    }
}

impl Session {
    fn conn(&mut self) -> Conn<'_> {
        match self {
            Self::PgTx(tx) => Conn::Pg(tx),
            Self::PgAuto(c) => Conn::Pg(c),
            Self::SqliteTx(tx) => Conn::Sqlite(tx),
            Self::SqliteAuto(c) => Conn::Sqlite(c),
        }
    }

    fn dialect(&self) -> Dialect {
        match self {
            Self::PgTx(_) | Self::PgAuto(_) => Dialect::Postgres,
            Self::SqliteTx(_) | Self::SqliteAuto(_) => Dialect::Sqlite,
        }
    }

    /// Runs a statement; returns the number of rows it changed.
    pub(crate) async fn execute(&mut self, sql: &'static Sql, args: Vec<Arg>) -> QueueResult<u64> {
        let text = sql.get(self.dialect());
        Ok(match self.conn() {
            Conn::Pg(c) => bind_pg(text, args).execute(c).await?.rows_affected(),
            Conn::Sqlite(c) => bind_sqlite(text, args).execute(c).await?.rows_affected(),
        })
    }

    pub(crate) async fn fetch_all(
        &mut self,
        sql: &'static Sql,
        args: Vec<Arg>,
    ) -> QueueResult<Vec<DbRow>> {
        let text = sql.get(self.dialect());
        Ok(match self.conn() {
            Conn::Pg(c) => bind_pg(text, args)
                .fetch_all(c)
                .await?
                .into_iter()
                .map(DbRow::Pg)
                .collect(),
            Conn::Sqlite(c) => bind_sqlite(text, args)
                .fetch_all(c)
                .await?
                .into_iter()
                .map(DbRow::Sqlite)
                .collect(),
        })
    }

    pub(crate) async fn fetch_optional(
        &mut self,
        sql: &'static Sql,
        args: Vec<Arg>,
    ) -> QueueResult<Option<DbRow>> {
        let text = sql.get(self.dialect());
        Ok(match self.conn() {
            Conn::Pg(c) => bind_pg(text, args).fetch_optional(c).await?.map(DbRow::Pg),
            Conn::Sqlite(c) => bind_sqlite(text, args)
                .fetch_optional(c)
                .await?
                .map(DbRow::Sqlite),
        })
    }

    pub(crate) async fn fetch_one(
        &mut self,
        sql: &'static Sql,
        args: Vec<Arg>,
    ) -> QueueResult<DbRow> {
        let text = sql.get(self.dialect());
        Ok(match self.conn() {
            Conn::Pg(c) => DbRow::Pg(bind_pg(text, args).fetch_one(c).await?),
            Conn::Sqlite(c) => DbRow::Sqlite(bind_sqlite(text, args).fetch_one(c).await?),
        })
    }

    /// Commits a transaction; a no-op for autocommit sessions. Dropping a transaction without
    /// committing rolls it back.
    pub(crate) async fn commit(self) -> QueueResult<()> {
        match self {
            Self::PgTx(tx) => tx.commit().await?,
            Self::SqliteTx(tx) => tx.commit().await?,
            Self::PgAuto(_) | Self::SqliteAuto(_) => {}
        }
        Ok(())
    }
}

#[cfg(all(test, unix))]
mod private_file_tests {
    use std::os::unix::fs::PermissionsExt;

    use super::private_database_file;

    fn mode(path: &std::path::Path) -> u32 {
        std::fs::metadata(path)
            .expect("metadata")
            .permissions()
            .mode()
            & 0o777
    }

    #[test]
    fn a_new_database_file_is_the_owners_only_and_an_old_one_becomes_so() {
        let dir = tempfile::tempdir().expect("tempdir");
        let new = dir.path().join("queue.db");
        private_database_file(&new).expect("create");
        assert_eq!(mode(&new), 0o600);
        let old = dir.path().join("old.db");
        std::fs::write(&old, b"").expect("write");
        std::fs::set_permissions(&old, std::fs::Permissions::from_mode(0o644)).expect("chmod");
        private_database_file(&old).expect("tighten");
        assert_eq!(mode(&old), 0o600);
        // A folder that does not exist is left for SQLite to report.
        private_database_file(&dir.path().join("missing/queue.db")).expect("left alone");
    }
}
