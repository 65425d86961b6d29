//! A map of values that expire: what the dashboard's per-tenant answers are cached in, so many
//! viewers polling the same tenant (or batch) cost one query per interval. While one caller
//! recomputes a stale value, the others get the stale one instead of waiting or piling on.

use std::collections::HashMap;
use std::future::Future;
use std::hash::Hash;
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::Mutex;

/// One cached value.
#[derive(Debug)]
struct Entry<V> {
    taken: Instant,
    value: Arc<V>,
    /// A caller is recomputing it.
    refreshing: bool,
}

/// Values by key, each kept for the `ttl` given when it is read.
#[derive(Debug)]
pub(crate) struct TtlCache<K, V> {
    entries: Mutex<HashMap<K, Entry<V>>>,
    /// Entries beyond this many are dropped, oldest first, when one is added.
    capacity: usize,
}

impl<K: Eq + Hash + Clone, V> TtlCache<K, V> {
    pub(crate) fn new(capacity: usize) -> Self {
        Self {
            entries: Mutex::new(HashMap::new()),
            capacity: capacity.max(1),
        }
    }

    /// The value of `key` if computed less than `ttl` ago; else, when another caller is already
    /// recomputing it, the stale value; else `compute()`'s (cached on success). The map is not
    /// locked while computing, so one key's query never waits for another's.
    pub(crate) async fn get_or_compute<E, F>(
        &self,
        key: K,
        ttl: Duration,
        compute: F,
    ) -> Result<Arc<V>, E>
    where
        F: Future<Output = Result<V, E>>,
    {
        {
            let mut entries = self.entries.lock().await;
            if let Some(entry) = entries.get_mut(&key) {
                if entry.taken.elapsed() < ttl || entry.refreshing {
                    return Ok(Arc::clone(&entry.value));
                }
                entry.refreshing = true;
            }
        }
        let computed = compute.await;
        let mut entries = self.entries.lock().await;
        let value = match computed {
            Ok(value) => Arc::new(value),
            Err(e) => {
                if let Some(entry) = entries.get_mut(&key) {
                    entry.refreshing = false;
                }
                return Err(e);
            }
        };
        if entries.len() >= self.capacity && !entries.contains_key(&key) {
            let oldest = entries
                .iter()
                .min_by_key(|(_, entry)| entry.taken)
                .map(|(k, _)| k.clone());
            if let Some(oldest) = oldest {
                entries.remove(&oldest);
            }
        }
        let entry = Entry {
            taken: Instant::now(),
            value: Arc::clone(&value),
            refreshing: false,
        };
        entries.insert(key, entry);
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use tokio::sync::Notify;

    use super::*;

    #[tokio::test]
    async fn a_value_is_computed_once_per_ttl_and_the_oldest_goes_first() {
        let cache: TtlCache<&str, u32> = TtlCache::new(2);
        let calls = AtomicU32::new(0);
        let compute = || async { Ok::<_, ()>(calls.fetch_add(1, Ordering::SeqCst)) };
        let hour = Duration::from_secs(3600);
        let get = |key, ttl| cache.get_or_compute(key, ttl, compute());
        assert_eq!(*get("a", hour).await.unwrap(), 0);
        assert_eq!(*get("a", hour).await.unwrap(), 0, "cached");
        assert_eq!(*get("a", Duration::ZERO).await.unwrap(), 1, "expired");
        assert_eq!(*get("b", hour).await.unwrap(), 2);
        assert_eq!(*get("c", hour).await.unwrap(), 3, "a, the oldest, goes");
        assert_eq!(*get("b", hour).await.unwrap(), 2, "b stays");
        assert_eq!(*get("a", hour).await.unwrap(), 4, "a was dropped");
        let failed: Result<_, &str> = cache.get_or_compute("d", hour, async { Err("down") }).await;
        assert!(failed.is_err());
        assert_eq!(*get("d", hour).await.unwrap(), 5, "errors are not cached");
    }

    #[tokio::test]
    async fn while_one_caller_recomputes_the_others_get_the_stale_value() {
        let cache: TtlCache<&str, u32> = TtlCache::new(4);
        let hour = Duration::from_secs(3600);
        cache
            .get_or_compute("k", hour, async { Ok::<_, ()>(1) })
            .await
            .unwrap();
        let release = Notify::new();
        let slow = cache.get_or_compute("k", Duration::ZERO, async {
            release.notified().await;
            Ok::<_, ()>(2)
        });
        let meanwhile = async {
            // Let the slow caller claim the refresh first.
            tokio::task::yield_now().await;
            let stale = *cache
                .get_or_compute("k", Duration::ZERO, async { Ok::<_, ()>(99) })
                .await
                .unwrap();
            release.notify_one();
            stale
        };
        let (fresh, stale) = tokio::join!(slow, meanwhile);
        assert_eq!(
            stale, 1,
            "served the stale value instead of computing again"
        );
        assert_eq!(*fresh.unwrap(), 2);
        let after = cache
            .get_or_compute("k", hour, async { Ok::<_, ()>(3) })
            .await
            .unwrap();
        assert_eq!(*after, 2, "the refreshed value is cached");
    }
}
