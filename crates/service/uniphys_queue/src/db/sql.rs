//! SQL written once for both databases: a template with a few dialect tokens, rendered once per
//! dialect and cached (so sqlx's statement cache sees one string per statement).
//!
//! Tokens: `{now}` is the database clock in Unix milliseconds (Postgres `statement_timestamp()`,
//! fixed within a statement; SQLite `unixepoch('subsec')`, fixed within a step); `{skip_locked}` is
//! `FOR UPDATE SKIP LOCKED` on Postgres and nothing on SQLite, whose writers are serialized anyway;
//! `{for_update}` likewise; `{in_list_N}` tests membership in the text or integer list bound as
//! `$N` (an array on Postgres, a JSON array on SQLite). Parameters are `$N` in both dialects.

use std::sync::OnceLock;

/// Which SQL dialect to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Dialect {
    Postgres,
    Sqlite,
}

/// One statement template (or one per dialect, where the best plan needs different SQL) and its
/// two rendered forms.
pub(crate) struct Sql {
    postgres_template: &'static str,
    sqlite_template: &'static str,
    postgres: OnceLock<String>,
    sqlite: OnceLock<String>,
}

impl Sql {
    pub(crate) const fn new(template: &'static str) -> Self {
        Self::per_dialect(template, template)
    }

    /// A statement written separately for each dialect (still rendered for tokens).
    pub(crate) const fn per_dialect(postgres: &'static str, sqlite: &'static str) -> Self {
        Self {
            postgres_template: postgres,
            sqlite_template: sqlite,
            postgres: OnceLock::new(),
            sqlite: OnceLock::new(),
        }
    }

    /// Returns the statement for `dialect`, rendering it on first use.
    pub(crate) fn get(&'static self, dialect: Dialect) -> &'static str {
        let (cell, template) = match dialect {
            Dialect::Postgres => (&self.postgres, self.postgres_template),
            Dialect::Sqlite => (&self.sqlite, self.sqlite_template),
        };
        cell.get_or_init(|| render(template, dialect))
    }
}

fn render(template: &str, dialect: Dialect) -> String {
    let (now, skip_locked, for_update) = match dialect {
        Dialect::Postgres => (
            "CAST(EXTRACT(EPOCH FROM statement_timestamp()) * 1000 AS BIGINT)",
            "FOR UPDATE SKIP LOCKED",
            "FOR UPDATE",
        ),
        Dialect::Sqlite => ("CAST(unixepoch('subsec') * 1000 AS INTEGER)", "", ""),
    };
    let mut sql = template
        .replace("{now}", now)
        .replace("{skip_locked}", skip_locked)
        .replace("{for_update}", for_update);
    for n in 1..=9 {
        let token = format!("{{in_list_{n}}}");
        if sql.contains(&token) {
            let membership = match dialect {
                Dialect::Postgres => format!("= ANY(${n})"),
                Dialect::Sqlite => format!("IN (SELECT value FROM json_each(${n}))"),
            };
            sql = sql.replace(&token, &membership);
        }
    }
    debug_assert!(!sql.contains('{'), "unknown token left in {sql}");
    sql
}

#[cfg(test)]
mod tests {
    use super::*;

    static PROBE: Sql = Sql::new("SELECT {now} WHERE name {in_list_2} {skip_locked}");

    #[test]
    fn templates_render_per_dialect() {
        let pg = PROBE.get(Dialect::Postgres);
        assert!(pg.contains("statement_timestamp()"));
        assert!(pg.contains("= ANY($2)"));
        assert!(pg.ends_with("FOR UPDATE SKIP LOCKED"));
        let lite = PROBE.get(Dialect::Sqlite);
        assert!(lite.contains("unixepoch('subsec')"));
        assert!(lite.contains("IN (SELECT value FROM json_each($2))"));
        assert!(!lite.contains("FOR UPDATE"));
    }
}
