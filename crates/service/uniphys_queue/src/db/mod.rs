//! The one place that talks to sqlx: pools, sessions (a transaction or a single autocommit
//! statement), bound arguments and rows, each an enum over Postgres and SQLite so the queue's
//! logic is written once.

mod bind;
mod row;
mod session;
pub(crate) mod sql;

pub(crate) use bind::Arg;
pub(crate) use row::DbRow;
pub(crate) use session::{Db, Session};
pub(crate) use sql::{Dialect, Sql};

/// Builds a `Vec<Arg>` from values that convert into [`Arg`].
macro_rules! args {
    ($($value:expr),* $(,)?) => {
        vec![$($crate::db::Arg::from($value)),*]
    };
}
pub(crate) use args;
