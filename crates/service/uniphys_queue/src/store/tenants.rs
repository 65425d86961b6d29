//! Tenants and their API keys. Keys are stored as SHA-256 digests: a leaked table does not leak
//! keys, and lookup is one indexed equality (keys are long random tokens, so a fast hash is right).

use sha2::{Digest, Sha256};

use super::QueueStore;
use crate::db::{Sql, args};
use crate::{QueueError, QueueResult, TenantId};

static INSERT_TENANT: Sql =
    Sql::new("INSERT INTO tenants (name, created_at_ms) VALUES ($1, {now}) RETURNING id");
static INSERT_KEY: Sql = Sql::new(
    "INSERT INTO api_keys (tenant_id, key_sha256, label, created_at_ms) VALUES ($1, $2, $3, {now})",
);
static FIND_TENANT: Sql = Sql::new("SELECT id FROM tenants WHERE name = $1");
static FIND_KEY: Sql =
    Sql::new("SELECT tenant_id FROM api_keys WHERE key_sha256 = $1 AND revoked_at_ms IS NULL");
static REVOKE_TENANT_KEYS: Sql = Sql::new(
    "UPDATE api_keys SET revoked_at_ms = {now} WHERE tenant_id = $1 AND revoked_at_ms IS NULL",
);
static REVOKE_KEY: Sql = Sql::new(
    "UPDATE api_keys SET revoked_at_ms = {now} WHERE key_sha256 = $1 AND revoked_at_ms IS NULL",
);

fn key_digest(api_key: &str) -> Vec<u8> {
    Sha256::digest(api_key.as_bytes()).to_vec()
}

fn unique_to_exists(e: QueueError, what: &'static str) -> QueueError {
    match &e {
        QueueError::Database(sqlx::Error::Database(db)) if db.is_unique_violation() => {
            QueueError::AlreadyExists { what }
        }
        QueueError::Database(sqlx::Error::Database(db)) if db.is_foreign_key_violation() => {
            QueueError::Invalid(format!("{what} refers to an unknown tenant"))
        }
        _ => e,
    }
}

/// Longest tenant name, in characters.
pub const MAX_TENANT_NAME_CHARS: usize = 64;

/// Checks a tenant name: 1 to [`MAX_TENANT_NAME_CHARS`] letters, digits, `.`, `_` or `-`
/// (it appears in logs, metrics and object keys), not starting with `.` or `-`.
pub fn validate_tenant_name(name: &str) -> QueueResult<()> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-');
    let problem = if name.is_empty() {
        Some("it is empty".to_owned())
    } else if name.chars().count() > MAX_TENANT_NAME_CHARS {
        Some(format!(
            "it has {} characters (at most {MAX_TENANT_NAME_CHARS})",
            name.chars().count()
        ))
    } else if let Some(c) = name.chars().find(|&c| !allowed(c)) {
        Some(format!("it holds {c:?}"))
    } else if name.starts_with(['.', '-']) {
        Some("it starts with . or -".to_owned())
    } else {
        None
    };
    match problem {
        Some(problem) => Err(QueueError::Invalid(format!(
            "tenant name {name:?} is not valid: {problem}; use letters, digits, '.', '_' and '-'"
        ))),
        None => Ok(()),
    }
}

impl QueueStore {
    /// Creates a tenant; `Invalid` for a name [`validate_tenant_name`] refuses, `AlreadyExists`
    /// if the name is taken.
    pub async fn create_tenant(&self, name: &str) -> QueueResult<TenantId> {
        validate_tenant_name(name)?;
        let mut session = self.db.write_one().await?;
        let row = session
            .fetch_one(&INSERT_TENANT, args![name])
            .await
            .map_err(|e| unique_to_exists(e, "tenant"))?;
        Ok(TenantId(row.i64("id")?))
    }

    /// The tenant called `name`, if there is one.
    pub async fn tenant_by_name(&self, name: &str) -> QueueResult<Option<TenantId>> {
        let mut session = self.db.read().await?;
        let row = session.fetch_optional(&FIND_TENANT, args![name]).await?;
        row.map(|r| r.i64("id").map(TenantId)).transpose()
    }

    /// Stores the digest of `api_key` for `tenant`. The caller generates the key (at least 128
    /// random bits) and shows it once; it is not recoverable from the store.
    pub async fn add_api_key(
        &self,
        tenant: TenantId,
        api_key: &str,
        label: &str,
    ) -> QueueResult<()> {
        if api_key.len() < 16 {
            return Err(QueueError::Invalid(
                "an API key needs at least 16 bytes".into(),
            ));
        }
        let mut session = self.db.write_one().await?;
        session
            .execute(&INSERT_KEY, args![tenant.0, key_digest(api_key), label])
            .await
            .map_err(|e| unique_to_exists(e, "api key"))?;
        Ok(())
    }

    /// Revokes every key of `tenant`; returns how many were in use.
    pub async fn revoke_tenant_keys(&self, tenant: TenantId) -> QueueResult<u64> {
        let mut session = self.db.write_one().await?;
        session.execute(&REVOKE_TENANT_KEYS, args![tenant.0]).await
    }

    /// Returns the tenant of a valid (stored, not revoked) API key.
    pub async fn tenant_for_api_key(&self, api_key: &str) -> QueueResult<Option<TenantId>> {
        let mut session = self.db.read().await?;
        let row = session
            .fetch_optional(&FIND_KEY, args![key_digest(api_key)])
            .await?;
        row.map(|r| r.i64("tenant_id").map(TenantId)).transpose()
    }

    /// Revokes an API key; returns false if it was unknown or already revoked.
    pub async fn revoke_api_key(&self, api_key: &str) -> QueueResult<bool> {
        let mut session = self.db.write_one().await?;
        Ok(session
            .execute(&REVOKE_KEY, args![key_digest(api_key)])
            .await?
            > 0)
    }
}
