//! A result row of either database, read by column name.

use serde::de::DeserializeOwned;
use serde_json::Value;
use sqlx::Row;
use sqlx::postgres::PgRow;
use sqlx::sqlite::SqliteRow;
use sqlx::types::Json;

use crate::{QueueError, QueueResult};

/// One row of a result set.
pub(crate) enum DbRow {
    Pg(PgRow),
    Sqlite(SqliteRow),
}

impl DbRow {
    pub(crate) fn i64(&self, column: &str) -> QueueResult<i64> {
        Ok(match self {
            Self::Pg(r) => r.try_get(column)?,
            Self::Sqlite(r) => r.try_get(column)?,
        })
    }

    pub(crate) fn opt_i64(&self, column: &str) -> QueueResult<Option<i64>> {
        Ok(match self {
            Self::Pg(r) => r.try_get(column)?,
            Self::Sqlite(r) => r.try_get(column)?,
        })
    }

    /// Reads a non-negative count or attempt number.
    pub(crate) fn u32(&self, column: &str) -> QueueResult<u32> {
        let v = self.i64(column)?;
        u32::try_from(v)
            .map_err(|_| QueueError::CorruptRow(format!("{column} = {v} is out of range")))
    }

    /// Reads a non-negative count.
    pub(crate) fn u64(&self, column: &str) -> QueueResult<u64> {
        let v = self.i64(column)?;
        u64::try_from(v).map_err(|_| QueueError::CorruptRow(format!("{column} = {v} is negative")))
    }

    pub(crate) fn text(&self, column: &str) -> QueueResult<String> {
        Ok(match self {
            Self::Pg(r) => r.try_get(column)?,
            Self::Sqlite(r) => r.try_get(column)?,
        })
    }

    pub(crate) fn opt_text(&self, column: &str) -> QueueResult<Option<String>> {
        Ok(match self {
            Self::Pg(r) => r.try_get(column)?,
            Self::Sqlite(r) => r.try_get(column)?,
        })
    }

    pub(crate) fn opt_json<T: DeserializeOwned>(&self, column: &str) -> QueueResult<Option<T>> {
        let value: Option<Json<Value>> = match self {
            Self::Pg(r) => r.try_get(column)?,
            Self::Sqlite(r) => r.try_get(column)?,
        };
        value
            .map(|Json(v)| {
                serde_json::from_value(v)
                    .map_err(|e| QueueError::CorruptRow(format!("{column}: {e}")))
            })
            .transpose()
    }

    pub(crate) fn json<T: DeserializeOwned>(&self, column: &str) -> QueueResult<T> {
        self.opt_json(column)?
            .ok_or_else(|| QueueError::CorruptRow(format!("{column} is null")))
    }
}
