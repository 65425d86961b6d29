//! API keys: generated here (the store keeps only their digest) and, for the embedded server, a
//! local tenant whose key is kept in the data directory so `uniphys submit` finds it.

use std::io::Read;
use std::path::Path;

use anyhow::Context;
use uniphys_queue::{QueueStore, TenantId};

/// Name of the tenant `serve` creates for local use.
pub const LOCAL_TENANT: &str = "local";

/// A new API key: `uk_` and 48 hex digits (192 random bits from the OS).
pub fn new_api_key() -> anyhow::Result<String> {
    let mut bytes = [0u8; 24];
    std::fs::File::open("/dev/urandom")
        .and_then(|mut f| f.read_exact(&mut bytes))
        .context("cannot read random bytes for an API key")?;
    Ok(format!("uk_{}", hex::encode(bytes)))
}

/// Creates tenant `name` and gives it a new key, which is returned. An existing tenant is
/// refused unless `rotate`: then its keys are revoked and the new one replaces them.
pub async fn create_tenant_key(
    store: &QueueStore,
    name: &str,
    label: &str,
    rotate: bool,
) -> anyhow::Result<(TenantId, String)> {
    let tenant = match store.tenant_by_name(name).await? {
        Some(id) if rotate => {
            store.revoke_tenant_keys(id).await?;
            id
        }
        Some(id) => anyhow::bail!(
            "tenant {name:?} exists ({id}) and its keys stay valid; to replace them with a new key, run `uniphys tenant create {name} --rotate-key` (its old keys then stop working)"
        ),
        None => store
            .create_tenant(name)
            .await
            .with_context(|| format!("cannot create tenant {name:?}"))?,
    };
    let key = new_api_key()?;
    store.add_api_key(tenant, &key, label).await?;
    Ok((tenant, key))
}

/// The local tenant's key: read from `file` if it still opens the store, else a new one written
/// there (mode 0600).
pub async fn ensure_local_key(store: &QueueStore, file: &Path) -> anyhow::Result<String> {
    if let Ok(existing) = std::fs::read_to_string(file) {
        let existing = existing.trim().to_owned();
        if store.tenant_for_api_key(&existing).await?.is_some() {
            return Ok(existing);
        }
    }
    // The file is the local tenant's only holder of a key: a lost one is replaced.
    let (_, key) = create_tenant_key(store, LOCAL_TENANT, "serve", true).await?;
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir)?;
    }
    write_private(file, &key).with_context(|| format!("cannot write {}", file.display()))?;
    Ok(key)
}

#[cfg(unix)]
fn write_private(file: &Path, key: &str) -> std::io::Result<()> {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .mode(0o600)
        .open(file)?;
    writeln!(f, "{key}")
}

#[cfg(not(unix))]
fn write_private(file: &Path, key: &str) -> std::io::Result<()> {
    std::fs::write(file, format!("{key}\n"))
}
