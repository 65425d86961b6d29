use bytes::Bytes;
use futures::StreamExt;
use object_store::path::Path as StorePath;
use object_store::{ObjectStoreExt, PutMode, PutOptions, PutPayload};
use sha2::{Digest, Sha256};

use crate::key::validate_key;
use crate::{ArtifactStore, StorageError, StorageResult};

/// What a create-only write found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PutOutcome {
    /// The object did not exist and was written.
    Created,
    /// The same content (same SHA-256) was already stored under the key; nothing was written.
    AlreadyPresent,
}

/// SHA-256 of some content.
pub(crate) type ContentDigest = [u8; 32];

impl ArtifactStore {
    /// Writes `bytes` at `key` only if nothing is stored there yet (create-only, `If-None-Match: *`
    /// on S3). When the key already exists, the stored content is read back and compared by SHA-256:
    /// the same content is [`PutOutcome::AlreadyPresent`] (a re-run or a retried request), different
    /// content is [`StorageError::Conflict`] and the stored object is left unchanged.
    ///
    /// Stores that do not implement create-only puts fall back to "head, compare, then put"; that
    /// fallback cannot tell two writers racing on the same key apart, the conditional put can.
    pub async fn put_once(&self, key: &str, bytes: impl Into<Bytes>) -> StorageResult<PutOutcome> {
        validate_key(key)?;
        let bytes: Bytes = bytes.into();
        let digest: ContentDigest = Sha256::digest(&bytes).into();
        let path = StorePath::from(key);
        let create = PutOptions::from(PutMode::Create);
        match self
            .store
            .put_opts(&path, PutPayload::from(bytes.clone()), create)
            .await
        {
            Ok(_) => Ok(PutOutcome::Created),
            Err(object_store::Error::AlreadyExists { .. }) => {
                self.same_or_conflict(key, digest).await
            }
            Err(object_store::Error::NotImplemented { .. }) => {
                if self.head(key).await?.is_some() {
                    return self.same_or_conflict(key, digest).await;
                }
                self.store
                    .put(&path, PutPayload::from(bytes))
                    .await
                    .map_err(|source| StorageError::from_store(key, source))?;
                Ok(PutOutcome::Created)
            }
            Err(source) => Err(StorageError::from_store(key, source)),
        }
    }

    /// [`PutOutcome::AlreadyPresent`] when the object at `key` has SHA-256 `digest`, else
    /// [`StorageError::Conflict`].
    pub(crate) async fn same_or_conflict(
        &self,
        key: &str,
        digest: ContentDigest,
    ) -> StorageResult<PutOutcome> {
        if self.stored_digest(key).await? == digest {
            Ok(PutOutcome::AlreadyPresent)
        } else {
            Err(StorageError::Conflict {
                key: key.to_owned(),
            })
        }
    }

    /// SHA-256 of the object at `key`, streamed (the object is never held whole in memory).
    pub(crate) async fn stored_digest(&self, key: &str) -> StorageResult<ContentDigest> {
        let map = |source| StorageError::from_store(key, source);
        let result = self.store.get(&StorePath::from(key)).await.map_err(map)?;
        let mut stream = result.into_stream();
        let mut hasher = Sha256::new();
        while let Some(chunk) = stream.next().await {
            hasher.update(chunk.map_err(map)?);
        }
        Ok(hasher.finalize().into())
    }

    /// Hex SHA-256 of the object at `key` (for manifests and checks).
    pub async fn sha256_hex(&self, key: &str) -> StorageResult<String> {
        validate_key(key)?;
        Ok(hex::encode(self.stored_digest(key).await?))
    }
}
