//! The schema migrations, embedded from the workspace's `migrations/` folder at build time and
//! applied at run time with `sqlx::migrate::Migrator` (no database needed to build, and no files
//! needed next to the binary). One list per dialect; the files are `NNNN_name.{up,down}.sql`.

use std::borrow::Cow;

use sqlx::migrate::{Migration, MigrationType, Migrator};
use sqlx::{AssertSqlSafe, SqlSafeStr};

use crate::db::Dialect;

/// (version, description, up, down)
type Embedded = (i64, &'static str, &'static str, &'static str);

const POSTGRES: &[Embedded] = &[
    (
        1,
        "queue",
        include_str!("../../../../migrations/postgres/0001_queue.up.sql"),
        include_str!("../../../../migrations/postgres/0001_queue.down.sql"),
    ),
    (
        2,
        "dashboard",
        include_str!("../../../../migrations/postgres/0002_dashboard.up.sql"),
        include_str!("../../../../migrations/postgres/0002_dashboard.down.sql"),
    ),
    (
        3,
        "claim_order",
        include_str!("../../../../migrations/postgres/0003_claim_order.up.sql"),
        include_str!("../../../../migrations/postgres/0003_claim_order.down.sql"),
    ),
];

const SQLITE: &[Embedded] = &[
    (
        1,
        "queue",
        include_str!("../../../../migrations/sqlite/0001_queue.up.sql"),
        include_str!("../../../../migrations/sqlite/0001_queue.down.sql"),
    ),
    (
        2,
        "dashboard",
        include_str!("../../../../migrations/sqlite/0002_dashboard.up.sql"),
        include_str!("../../../../migrations/sqlite/0002_dashboard.down.sql"),
    ),
    (
        3,
        "claim_order",
        include_str!("../../../../migrations/sqlite/0003_claim_order.up.sql"),
        include_str!("../../../../migrations/sqlite/0003_claim_order.down.sql"),
    ),
];

/// Builds the migrator for `dialect`.
pub(crate) fn migrator(dialect: Dialect) -> Migrator {
    let embedded = match dialect {
        Dialect::Postgres => POSTGRES,
        Dialect::Sqlite => SQLITE,
    };
    let mut migrations = Vec::with_capacity(embedded.len() * 2);
    for &(version, description, up, down) in embedded {
        for (kind, sql) in [
            (MigrationType::ReversibleUp, up),
            (MigrationType::ReversibleDown, down),
        ] {
            migrations.push(Migration::new(
                version,
                Cow::Borrowed(description),
                kind,
                AssertSqlSafe(sql).into_sql_str(),
                false,
            ));
        }
    }
    Migrator::with_migrations(migrations)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every file in `migrations/<dialect>/` is embedded, and nothing else.
    #[test]
    fn every_migration_file_is_embedded() {
        for (dir, embedded) in [("postgres", POSTGRES), ("sqlite", SQLITE)] {
            let path = format!("{}/../../../migrations/{dir}", env!("CARGO_MANIFEST_DIR"));
            let mut on_disk: Vec<String> = std::fs::read_dir(&path)
                .expect("migrations folder exists")
                .map(|e| {
                    e.expect("readable entry")
                        .file_name()
                        .to_string_lossy()
                        .into_owned()
                })
                .collect();
            on_disk.sort();
            let mut listed: Vec<String> = embedded
                .iter()
                .flat_map(|(v, d, _, _)| {
                    [format!("{v:04}_{d}.down.sql"), format!("{v:04}_{d}.up.sql")]
                })
                .collect();
            listed.sort();
            assert_eq!(
                on_disk, listed,
                "migrations/{dir} and the embedded list differ"
            );
        }
    }
}
