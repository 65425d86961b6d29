//! Table health for monitoring: live and dead rows of the queue's tables (Postgres only; a queue
//! table that vacuum cannot keep up with slows every claim).

use super::QueueStore;
use crate::QueueResult;
use crate::db::{Dialect, Sql, args};

/// Row counts of one table, from Postgres's statistics collector (approximate).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TableHealth {
    /// The table.
    pub table: String,
    /// Estimated live rows.
    pub live_rows: u64,
    /// Estimated dead rows not yet vacuumed.
    pub dead_rows: u64,
}

static PG_TABLES: Sql = Sql::new(
    "SELECT CAST(relname AS TEXT) AS relname, n_live_tup, n_dead_tup FROM pg_stat_user_tables
     WHERE schemaname = current_schema()
     ORDER BY relname",
);

impl QueueStore {
    /// Returns live and dead row estimates of the queue's tables, sorted by table; empty on
    /// SQLite, which has no such statistics (and no vacuum debt to watch in embedded use).
    pub async fn table_health(&self) -> QueueResult<Vec<TableHealth>> {
        if self.db.dialect() == Dialect::Sqlite {
            return Ok(Vec::new());
        }
        let mut session = self.db.read().await?;
        let rows = session.fetch_all(&PG_TABLES, args![]).await?;
        rows.iter()
            .map(|row| {
                Ok(TableHealth {
                    table: row.text("relname")?,
                    live_rows: row.u64("n_live_tup")?,
                    dead_rows: row.u64("n_dead_tup")?,
                })
            })
            .collect()
    }
}
