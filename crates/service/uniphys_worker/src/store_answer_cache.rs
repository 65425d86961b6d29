//! The LVLM answer cache in the fleet's object store, so a stage retried on another worker does
//! not pay for the answers the first attempt already received.

use std::path::PathBuf;

use uniphys_lvlm::{AnswerCache, CachedAnswer, LvlmError, LvlmResult};
use uniphys_storage::ArtifactStore;

/// Answers stored as `{prefix}/{digest}.json`. An entry that cannot be read or parsed is a
/// miss (the request is sent again); one that cannot be written is an error.
pub struct StoreAnswerCache {
    store: ArtifactStore,
    prefix: String,
    runtime: tokio::runtime::Handle,
}

impl StoreAnswerCache {
    /// A cache under `prefix` of `store`; `runtime` runs the store's calls, so the cache must
    /// not be used from one of its async tasks (stages run on blocking threads).
    #[must_use]
    pub fn new(store: ArtifactStore, prefix: &str, runtime: tokio::runtime::Handle) -> Self {
        Self {
            store,
            prefix: prefix.trim_end_matches('/').to_owned(),
            runtime,
        }
    }

    fn key(&self, digest: &str) -> String {
        format!("{}/{digest}.json", self.prefix)
    }

    fn error(&self, digest: &str, error: impl std::fmt::Display) -> LvlmError {
        LvlmError::Cache {
            path: PathBuf::from(self.key(digest)),
            source: std::io::Error::other(error.to_string()),
        }
    }
}

impl AnswerCache for StoreAnswerCache {
    fn get(&self, digest: &str) -> Option<CachedAnswer> {
        let bytes = self
            .runtime
            .block_on(self.store.get(&self.key(digest)))
            .ok()?;
        serde_json::from_slice(&bytes).ok()
    }

    fn put(&self, digest: &str, answer: &CachedAnswer) -> LvlmResult<()> {
        let bytes = serde_json::to_vec(answer).map_err(|e| self.error(digest, e))?;
        self.runtime
            .block_on(self.store.put(&self.key(digest), bytes))
            .map_err(|e| self.error(digest, e))
    }

    fn remove(&self, digest: &str) -> LvlmResult<()> {
        self.runtime
            .block_on(self.store.delete(&self.key(digest)))
            .map_err(|e| self.error(digest, e))
    }
}

#[cfg(test)]
mod tests {
    use uniphys_lvlm::Usage;

    use super::*;

    fn answer(text: &str) -> CachedAnswer {
        CachedAnswer {
            text: text.to_owned(),
            usage: Usage::default(),
            model: "m".to_owned(),
            finish_reason: Some("stop".to_owned()),
        }
    }

    #[test]
    fn answers_round_trip_and_two_workers_share_them() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        let dir = tempfile::tempdir().unwrap();
        let store = ArtifactStore::local(dir.path()).unwrap();
        let first = StoreAnswerCache::new(store.clone(), "lvlm-answers/", runtime.handle().clone());
        let second = StoreAnswerCache::new(store.clone(), "lvlm-answers", runtime.handle().clone());
        assert_eq!(first.get("abc"), None);
        first.put("abc", &answer("yes")).unwrap();
        assert_eq!(second.get("abc"), Some(answer("yes")));
        second.put("abc", &answer("no")).unwrap();
        assert_eq!(first.get("abc"), Some(answer("no")));
        first.remove("abc").unwrap();
        assert_eq!(second.get("abc"), None);
        // A corrupt entry is a miss, not an error.
        runtime
            .block_on(store.put("lvlm-answers/bad.json", b"{not json".to_vec()))
            .unwrap();
        assert_eq!(first.get("bad"), None);
    }
}
