//! Values bound to statement parameters, in a form both drivers accept: lists are Postgres
//! arrays and SQLite JSON arrays.

use serde_json::Value;
use sqlx::postgres::PgArguments;
use sqlx::query::Query;
use sqlx::sqlite::SqliteArguments;
use sqlx::types::Json;
use sqlx::{Postgres, Sqlite};

/// One bound parameter.
#[derive(Debug)]
pub(crate) enum Arg {
    I64(Option<i64>),
    Text(Option<String>),
    Bytes(Vec<u8>),
    Json(Option<Value>),
    /// A list of texts for `{in_list_N}` (or `unnest` on Postgres).
    TextList(Vec<String>),
    /// A list of integers for `{in_list_N}` (or `unnest` on Postgres).
    I64List(Vec<i64>),
}

impl From<i64> for Arg {
    fn from(v: i64) -> Self {
        Self::I64(Some(v))
    }
}
impl From<Option<i64>> for Arg {
    fn from(v: Option<i64>) -> Self {
        Self::I64(v)
    }
}
impl From<&str> for Arg {
    fn from(v: &str) -> Self {
        Self::Text(Some(v.to_owned()))
    }
}
impl From<String> for Arg {
    fn from(v: String) -> Self {
        Self::Text(Some(v))
    }
}
impl From<Option<String>> for Arg {
    fn from(v: Option<String>) -> Self {
        Self::Text(v)
    }
}
impl From<Vec<u8>> for Arg {
    fn from(v: Vec<u8>) -> Self {
        Self::Bytes(v)
    }
}
impl From<Value> for Arg {
    fn from(v: Value) -> Self {
        Self::Json(Some(v))
    }
}
impl From<Option<Value>> for Arg {
    fn from(v: Option<Value>) -> Self {
        Self::Json(v)
    }
}
impl From<Vec<String>> for Arg {
    fn from(v: Vec<String>) -> Self {
        Self::TextList(v)
    }
}
impl From<Vec<i64>> for Arg {
    fn from(v: Vec<i64>) -> Self {
        Self::I64List(v)
    }
}

pub(crate) fn bind_pg(sql: &'static str, args: Vec<Arg>) -> Query<'static, Postgres, PgArguments> {
    let mut query = sqlx::query::<Postgres>(sql);
    for arg in args {
        query = match arg {
            Arg::I64(v) => query.bind(v),
            Arg::Text(v) => query.bind(v),
            Arg::Bytes(v) => query.bind(v),
            Arg::Json(v) => query.bind(v.map(Json)),
            Arg::TextList(v) => query.bind(v),
            Arg::I64List(v) => query.bind(v),
        };
    }
    query
}

pub(crate) fn bind_sqlite(
    sql: &'static str,
    args: Vec<Arg>,
) -> Query<'static, Sqlite, SqliteArguments> {
    let mut query = sqlx::query::<Sqlite>(sql);
    for arg in args {
        query = match arg {
            Arg::I64(v) => query.bind(v),
            Arg::Text(v) => query.bind(v),
            Arg::Bytes(v) => query.bind(v),
            Arg::Json(v) => query.bind(v.map(Json)),
            Arg::TextList(v) => query.bind(Value::from(v).to_string()),
            Arg::I64List(v) => query.bind(Value::from(v).to_string()),
        };
    }
    query
}
