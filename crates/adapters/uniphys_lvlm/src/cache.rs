use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, PoisonError};

use crate::{LvlmError, LvlmResult, Usage};

/// A stored answer: what the model said and what the call cost when it was paid for.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CachedAnswer {
    /// The answer text.
    pub text: String,
    /// Usage of the original call.
    pub usage: Usage,
    /// The model that answered.
    pub model: String,
    /// `finish_reason` of the original call.
    pub finish_reason: Option<String>,
}

/// Answers keyed by request digest ([`ChatRequest::request_digest`](crate::ChatRequest)), so
/// a retried stage does not pay twice.
pub trait AnswerCache: Send + Sync {
    /// The answer stored for `digest`, if any (an unreadable entry is a miss).
    fn get(&self, digest: &str) -> Option<CachedAnswer>;

    /// Stores `answer` for `digest`, replacing any earlier one.
    ///
    /// # Errors
    /// [`LvlmError::Cache`] if it cannot be stored.
    fn put(&self, digest: &str, answer: &CachedAnswer) -> LvlmResult<()>;

    /// Forgets the answer for `digest` (e.g. one that failed validation), if any.
    ///
    /// # Errors
    /// [`LvlmError::Cache`] if an existing entry cannot be removed.
    fn remove(&self, digest: &str) -> LvlmResult<()>;
}

/// No cache: every request is sent.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoCache;

impl AnswerCache for NoCache {
    fn get(&self, _digest: &str) -> Option<CachedAnswer> {
        None
    }

    fn put(&self, _digest: &str, _answer: &CachedAnswer) -> LvlmResult<()> {
        Ok(())
    }

    fn remove(&self, _digest: &str) -> LvlmResult<()> {
        Ok(())
    }
}

/// An in-process cache (lost with the process).
#[derive(Debug, Default)]
pub struct MemoryCache {
    answers: Mutex<BTreeMap<String, CachedAnswer>>,
}

impl MemoryCache {
    /// An empty cache.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of stored answers.
    #[must_use]
    pub fn len(&self) -> usize {
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .len()
    }

    /// Whether nothing is stored.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl AnswerCache for MemoryCache {
    fn get(&self, digest: &str) -> Option<CachedAnswer> {
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get(digest)
            .cloned()
    }

    fn put(&self, digest: &str, answer: &CachedAnswer) -> LvlmResult<()> {
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(digest.to_owned(), answer.clone());
        Ok(())
    }

    fn remove(&self, digest: &str) -> LvlmResult<()> {
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .remove(digest);
        Ok(())
    }
}

/// A directory of `<digest>.json` files, shared by processes: written to a temporary file and
/// renamed, so readers never see half an entry; an unreadable or corrupt file is a miss.
#[derive(Debug)]
pub struct DirCache {
    dir: PathBuf,
    temp_counter: AtomicU64,
}

impl DirCache {
    /// A cache in `dir`, created if missing.
    ///
    /// # Errors
    /// [`LvlmError::Cache`] if the directory cannot be created.
    pub fn new(dir: impl Into<PathBuf>) -> LvlmResult<Self> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(|source| LvlmError::Cache {
            path: dir.clone(),
            source,
        })?;
        Ok(Self {
            dir,
            temp_counter: AtomicU64::new(0),
        })
    }

    /// The directory.
    #[must_use]
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The file of `digest`, or `None` for a digest that is not a hex string (so a key can
    /// never name a path outside the directory).
    #[must_use]
    pub fn path_of(&self, digest: &str) -> Option<PathBuf> {
        let valid = !digest.is_empty()
            && digest.len() <= 128
            && digest.bytes().all(|b| b.is_ascii_hexdigit());
        valid.then(|| self.dir.join(format!("{digest}.json")))
    }

    fn invalid_digest(&self, digest: &str) -> LvlmError {
        LvlmError::Cache {
            path: self.dir.clone(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("cache key {digest:?} is not a hex digest"),
            ),
        }
    }
}

impl AnswerCache for DirCache {
    fn get(&self, digest: &str) -> Option<CachedAnswer> {
        let bytes = std::fs::read(self.path_of(digest)?).ok()?;
        serde_json::from_slice(&bytes).ok()
    }

    fn put(&self, digest: &str, answer: &CachedAnswer) -> LvlmResult<()> {
        let path = self
            .path_of(digest)
            .ok_or_else(|| self.invalid_digest(digest))?;
        let bytes = serde_json::to_vec_pretty(answer).map_err(|source| LvlmError::Encode {
            what: "a cached answer",
            source,
        })?;
        let temp = self.dir.join(format!(
            ".{digest}.{}.{}.tmp",
            std::process::id(),
            self.temp_counter.fetch_add(1, Ordering::Relaxed)
        ));
        let io_error = |path: &Path| {
            let path = path.to_path_buf();
            move |source| LvlmError::Cache { path, source }
        };
        std::fs::write(&temp, &bytes).map_err(io_error(&temp))?;
        std::fs::rename(&temp, &path).map_err(|source| {
            let _ = std::fs::remove_file(&temp);
            LvlmError::Cache {
                path: path.clone(),
                source,
            }
        })
    }

    fn remove(&self, digest: &str) -> LvlmResult<()> {
        let Some(path) = self.path_of(digest) else {
            return Ok(());
        };
        match std::fs::remove_file(&path) {
            Ok(()) => Ok(()),
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(source) => Err(LvlmError::Cache { path, source }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn answer(text: &str) -> CachedAnswer {
        CachedAnswer {
            text: text.to_owned(),
            usage: Usage {
                prompt_tokens: 10,
                completion_tokens: 3,
                reasoning_tokens: Some(1),
                estimated: false,
            },
            model: "m".to_owned(),
            finish_reason: Some("stop".to_owned()),
        }
    }

    const DIGEST: &str = "00aa11bb22cc33dd44ee55ff66778899aabbccddeeff00112233445566778899";

    #[test]
    fn memory_cache_stores_replaces_and_forgets() {
        let cache = MemoryCache::new();
        assert!(cache.get(DIGEST).is_none());
        cache.put(DIGEST, &answer("a")).unwrap();
        cache.put(DIGEST, &answer("b")).unwrap();
        assert_eq!(cache.get(DIGEST).unwrap().text, "b");
        assert_eq!(cache.len(), 1);
        cache.remove(DIGEST).unwrap();
        assert!(cache.is_empty());
    }

    #[test]
    fn dir_cache_round_trips_across_instances_and_leaves_no_temp_files() {
        let dir = tempfile::tempdir().unwrap();
        DirCache::new(dir.path())
            .unwrap()
            .put(DIGEST, &answer("x"))
            .unwrap();
        let reopened = DirCache::new(dir.path()).unwrap();
        assert_eq!(reopened.get(DIGEST).unwrap(), answer("x"));
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, vec![format!("{DIGEST}.json")]);
        reopened.remove(DIGEST).unwrap();
        reopened.remove(DIGEST).unwrap();
        assert!(reopened.get(DIGEST).is_none());
    }

    #[test]
    fn a_corrupt_entry_is_a_miss_and_can_be_overwritten() {
        let dir = tempfile::tempdir().unwrap();
        let cache = DirCache::new(dir.path()).unwrap();
        std::fs::write(cache.path_of(DIGEST).unwrap(), b"{\"text\": \"cut of").unwrap();
        assert!(cache.get(DIGEST).is_none());
        cache.put(DIGEST, &answer("fresh")).unwrap();
        assert_eq!(cache.get(DIGEST).unwrap().text, "fresh");
    }

    #[test]
    fn keys_that_are_not_hex_never_become_paths() {
        let dir = tempfile::tempdir().unwrap();
        let cache = DirCache::new(dir.path()).unwrap();
        assert!(cache.path_of("../etc/passwd").is_none());
        assert!(cache.put("../x", &answer("a")).is_err());
        assert!(cache.get("../x").is_none());
    }
}
