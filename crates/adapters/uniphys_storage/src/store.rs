use std::path::Path;
use std::sync::Arc;

use bytes::Bytes;
use futures::stream::BoxStream;
use futures::{StreamExt, TryStreamExt};
use object_store::local::LocalFileSystem;
use object_store::memory::InMemory;
use object_store::path::Path as StorePath;
use object_store::{ObjectStore, ObjectStoreExt, PutPayload};

use crate::key::validate_key;
use crate::{StorageError, StorageResult};

/// A store of artifacts addressed by `/`-separated keys.
#[derive(Debug, Clone)]
pub struct ArtifactStore {
    pub(crate) store: Arc<dyn ObjectStore>,
}

impl ArtifactStore {
    /// A store in a local directory, created if missing.
    pub fn local(dir: &Path) -> StorageResult<Self> {
        std::fs::create_dir_all(dir).map_err(|source| StorageError::CreateDir {
            path: dir.display().to_string(),
            source,
        })?;
        let fs = LocalFileSystem::new_with_prefix(dir).map_err(|source| StorageError::Store {
            key: dir.display().to_string(),
            source,
        })?;
        Ok(Self {
            store: Arc::new(fs),
        })
    }

    /// A store in memory (tests, dry runs).
    #[must_use]
    pub fn in_memory() -> Self {
        Self {
            store: Arc::new(InMemory::new()),
        }
    }

    /// A store over any `object_store` implementation (S3-compatible stores in production).
    #[must_use]
    pub fn from_object_store(store: Arc<dyn ObjectStore>) -> Self {
        Self { store }
    }

    /// Writes `bytes` at `key`, replacing what was there. Stage outputs should use
    /// [`ArtifactStore::put_once`], which never replaces different content.
    pub async fn put(&self, key: &str, bytes: Vec<u8>) -> StorageResult<()> {
        validate_key(key)?;
        self.store
            .put(&StorePath::from(key), PutPayload::from(bytes))
            .await
            .map(|_| ())
            .map_err(|source| StorageError::Store {
                key: key.to_owned(),
                source,
            })
    }

    /// Reads the object at `key`; a missing object is [`StorageError::NotFound`].
    pub async fn get(&self, key: &str) -> StorageResult<Vec<u8>> {
        validate_key(key)?;
        let map = |source| StorageError::from_store(key, source);
        let result = self.store.get(&StorePath::from(key)).await.map_err(map)?;
        Ok(result.bytes().await.map_err(map)?.to_vec())
    }

    /// The size in bytes of the object at `key`, or `None` when there is none.
    pub async fn head(&self, key: &str) -> StorageResult<Option<u64>> {
        validate_key(key)?;
        match self.store.head(&StorePath::from(key)).await {
            Ok(meta) => Ok(Some(meta.size)),
            Err(object_store::Error::NotFound { .. }) => Ok(None),
            Err(source) => Err(StorageError::from_store(key, source)),
        }
    }

    /// The size of the object at `key` and a stream of its bytes, for serving downloads without
    /// holding the object in memory. A missing object is [`StorageError::NotFound`].
    pub async fn get_stream(
        &self,
        key: &str,
    ) -> StorageResult<(u64, BoxStream<'static, StorageResult<Bytes>>)> {
        validate_key(key)?;
        let result = self
            .store
            .get(&StorePath::from(key))
            .await
            .map_err(|source| StorageError::from_store(key, source))?;
        let size = result.meta.size;
        let owned_key = key.to_owned();
        let stream = result
            .into_stream()
            .map_err(move |source| StorageError::from_store(&owned_key, source))
            .boxed();
        Ok((size, stream))
    }

    /// Deletes the object at `key`; a missing object is not an error.
    pub async fn delete(&self, key: &str) -> StorageResult<()> {
        validate_key(key)?;
        match self.store.delete(&StorePath::from(key)).await {
            Ok(()) | Err(object_store::Error::NotFound { .. }) => Ok(()),
            Err(source) => Err(StorageError::from_store(key, source)),
        }
    }

    /// Deletes every object under `prefix` (a whole key prefix, compared component by component);
    /// returns how many were deleted.
    pub async fn delete_prefix(&self, prefix: &str) -> StorageResult<usize> {
        validate_key(prefix)?;
        let map = |source| StorageError::from_store(prefix, source);
        let path = StorePath::from(prefix);
        let locations = self
            .store
            .list(Some(&path))
            .map_ok(|meta| meta.location)
            .boxed();
        let deleted: Vec<StorePath> = self
            .store
            .delete_stream(locations)
            .try_collect()
            .await
            .map_err(map)?;
        Ok(deleted.len())
    }

    /// Keys under `prefix`, sorted.
    pub async fn list(&self, prefix: &str) -> StorageResult<Vec<String>> {
        let map = |source| StorageError::Store {
            key: prefix.to_owned(),
            source,
        };
        let path = StorePath::from(prefix);
        let mut stream = self.store.list(Some(&path));
        let mut keys = Vec::new();
        while let Some(meta) = stream.next().await {
            keys.push(meta.map_err(map)?.location.to_string());
        }
        keys.sort();
        Ok(keys)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn local_store_writes_idempotently_and_lists_sorted() {
        let dir = tempfile::tempdir().unwrap();
        let store = ArtifactStore::local(&dir.path().join("out")).unwrap();
        store
            .put("a/meshes/x.obj", b"v 0 0 0\n".to_vec())
            .await
            .unwrap();
        store
            .put("a/model.urdf", b"<robot/>".to_vec())
            .await
            .unwrap();
        store
            .put("a/model.urdf", b"<robot/>".to_vec())
            .await
            .unwrap();
        assert_eq!(store.get("a/model.urdf").await.unwrap(), b"<robot/>");
        assert_eq!(
            store.list("a").await.unwrap(),
            ["a/meshes/x.obj", "a/model.urdf"]
        );
        assert!(dir.path().join("out/a/meshes/x.obj").is_file());
        assert!(store.put("../escape", vec![]).await.is_err());
    }
}
