use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

use futures::StreamExt;
use object_store::path::Path as StorePath;
use object_store::{ObjectStoreExt, WriteMultipart};
use sha2::{Digest, Sha256};
use tokio::io::{AsyncReadExt, AsyncWriteExt};

use crate::key::validate_key;
use crate::put_once::ContentDigest;
use crate::{ArtifactStore, PutOutcome, StorageError, StorageResult};

/// Top-level prefix of uploads in progress; a finished upload is copied to its key and removed.
/// Objects left here by a crashed process are garbage (an S3 lifecycle rule can expire them).
pub const STAGING_PREFIX: &str = ".staging";

/// Bytes read from a local file per step.
const READ_CHUNK_BYTES: usize = 1 << 20;
/// Multipart part size (S3 needs at least 5 MiB for all parts but the last).
const PART_BYTES: usize = 8 << 20;
/// Parts uploaded at the same time.
const PARTS_IN_FLIGHT: usize = 4;

impl ArtifactStore {
    /// Uploads the local file at `path` to `key` without reading it into memory (multipart upload),
    /// with the same create-only contract as [`ArtifactStore::put_once`]: an existing object with the
    /// same SHA-256 is [`PutOutcome::AlreadyPresent`], a different one is [`StorageError::Conflict`].
    ///
    /// The file is uploaded to a key under [`STAGING_PREFIX`] and then copied to `key` with a
    /// create-only copy (a hard link locally; on S3 a one-part multipart copy completed with
    /// `If-None-Match: *`). Where the store cannot copy create-only, the fallback checks for an
    /// existing object first and then copies, which cannot detect two writers racing on one key.
    pub async fn put_file(&self, key: &str, path: &Path) -> StorageResult<PutOutcome> {
        validate_key(key)?;
        if self.head(key).await?.is_some() {
            let digest = file_digest(path).await?;
            return self.same_or_conflict(key, digest).await;
        }
        let staging = StorePath::from(format!("{STAGING_PREFIX}/{}", unique_suffix()));
        let digest = self.upload_file(&staging, path).await?;
        let target = StorePath::from(key);
        let outcome = match self.store.copy_if_not_exists(&staging, &target).await {
            Ok(()) => Ok(PutOutcome::Created),
            Err(object_store::Error::AlreadyExists { .. }) => {
                self.same_or_conflict(key, digest).await
            }
            Err(
                object_store::Error::NotSupported { .. }
                | object_store::Error::NotImplemented { .. },
            ) => {
                if self.head(key).await?.is_some() {
                    self.same_or_conflict(key, digest).await
                } else {
                    self.store
                        .copy(&staging, &target)
                        .await
                        .map(|()| PutOutcome::Created)
                        .map_err(|source| StorageError::from_store(key, source))
                }
            }
            Err(source) => Err(StorageError::from_store(key, source)),
        };
        // Best effort: a staging object left behind is garbage, not a wrong artifact.
        let _ = self.store.delete(&staging).await;
        outcome
    }

    /// Multipart upload of the file at `path` to `location`; returns the file's SHA-256.
    async fn upload_file(&self, location: &StorePath, path: &Path) -> StorageResult<ContentDigest> {
        let local_err = |source| StorageError::LocalFile {
            path: path.display().to_string(),
            source,
        };
        let store_err = |source| StorageError::from_store(location.as_ref(), source);
        let mut file = tokio::fs::File::open(path).await.map_err(local_err)?;
        let upload = self
            .store
            .put_multipart(location)
            .await
            .map_err(store_err)?;
        let mut writer = WriteMultipart::new_with_chunk_size(upload, PART_BYTES);
        let mut hasher = Sha256::new();
        let mut buf = vec![0u8; READ_CHUNK_BYTES];
        loop {
            let read = match file.read(&mut buf).await {
                Ok(0) => break,
                Ok(n) => n,
                Err(source) => {
                    let _ = writer.abort().await;
                    return Err(local_err(source));
                }
            };
            hasher.update(&buf[..read]);
            if let Err(source) = writer.wait_for_capacity(PARTS_IN_FLIGHT).await {
                let _ = writer.abort().await;
                return Err(store_err(source));
            }
            writer.write(&buf[..read]);
        }
        writer.finish().await.map_err(store_err)?;
        Ok(hasher.finalize().into())
    }

    /// Streams the object at `key` into the local file `path` (parent directories are created);
    /// returns the number of bytes written. The data goes to `path` + `.partial` first and is
    /// renamed into place when complete, so `path` never holds a partial download.
    pub async fn get_to_file(&self, key: &str, path: &Path) -> StorageResult<u64> {
        let (_, mut stream) = self.get_stream(key).await?;
        let local_err = |source| StorageError::LocalFile {
            path: path.display().to_string(),
            source,
        };
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            tokio::fs::create_dir_all(parent).await.map_err(local_err)?;
        }
        let partial = partial_path(path);
        let result = async {
            let mut file = tokio::fs::File::create(&partial).await.map_err(local_err)?;
            let mut written = 0u64;
            while let Some(chunk) = stream.next().await {
                let chunk = chunk?;
                file.write_all(&chunk).await.map_err(local_err)?;
                written += chunk.len() as u64;
            }
            file.flush().await.map_err(local_err)?;
            file.sync_all().await.map_err(local_err)?;
            tokio::fs::rename(&partial, path).await.map_err(local_err)?;
            Ok(written)
        }
        .await;
        if result.is_err() {
            let _ = tokio::fs::remove_file(&partial).await;
        }
        result
    }
}

/// SHA-256 of a local file, streamed.
async fn file_digest(path: &Path) -> StorageResult<ContentDigest> {
    let local_err = |source| StorageError::LocalFile {
        path: path.display().to_string(),
        source,
    };
    let mut file = tokio::fs::File::open(path).await.map_err(local_err)?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; READ_CHUNK_BYTES];
    loop {
        let read = file.read(&mut buf).await.map_err(local_err)?;
        if read == 0 {
            return Ok(hasher.finalize().into());
        }
        hasher.update(&buf[..read]);
    }
}

fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

/// A name no other upload of this or another process uses: process id, clock and a counter.
fn unique_suffix() -> String {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    format!("{}-{nanos}-{n}", std::process::id())
}
