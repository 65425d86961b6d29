//! A map of values that expire: what the dashboard's per-tenant answers are cached in, so many
//! viewers polling the same tenant (or batch) cost one query per interval.

use std::collections::HashMap;
use std::future::Future;
use std::hash::Hash;
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::Mutex;

/// Values by key, each kept for the `ttl` given when it is read.
#[derive(Debug)]
pub(crate) struct TtlCache<K, V> {
    entries: Mutex<HashMap<K, (Instant, Arc<V>)>>,
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

    /// The value of `key` if computed less than `ttl` ago, else `compute()`'s (cached on
    /// success). The map is not locked while computing: one key's query never waits for
    /// another's; two callers of a stale key may both compute it.
    pub(crate) async fn get_or_compute<E, F>(
        &self,
        key: K,
        ttl: Duration,
        compute: F,
    ) -> Result<Arc<V>, E>
    where
        F: Future<Output = Result<V, E>>,
    {
        if let Some((taken, value)) = self.entries.lock().await.get(&key)
            && taken.elapsed() < ttl
        {
            return Ok(Arc::clone(value));
        }
        let value = Arc::new(compute.await?);
        let mut entries = self.entries.lock().await;
        if entries.len() >= self.capacity && !entries.contains_key(&key) {
            let oldest = entries
                .iter()
                .min_by_key(|(_, (taken, _))| *taken)
                .map(|(k, _)| k.clone());
            if let Some(oldest) = oldest {
                entries.remove(&oldest);
            }
        }
        entries.insert(key, (Instant::now(), Arc::clone(&value)));
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;

    #[tokio::test]
    async fn a_value_is_computed_once_per_ttl_and_the_oldest_goes_first() {
        let cache: TtlCache<&str, u32> = TtlCache::new(2);
        let calls = AtomicU32::new(0);
        let compute = || async { Ok::<_, ()>(calls.fetch_add(1, Ordering::SeqCst)) };
        let hour = Duration::from_secs(3600);
        assert_eq!(
            *cache.get_or_compute("a", hour, compute()).await.unwrap(),
            0
        );
        assert_eq!(
            *cache.get_or_compute("a", hour, compute()).await.unwrap(),
            0,
            "cached"
        );
        assert_eq!(
            *cache
                .get_or_compute("a", Duration::ZERO, compute())
                .await
                .unwrap(),
            1,
            "expired"
        );
        assert_eq!(
            *cache.get_or_compute("b", hour, compute()).await.unwrap(),
            2
        );
        assert_eq!(
            *cache.get_or_compute("c", hour, compute()).await.unwrap(),
            3,
            "a, the oldest, goes"
        );
        assert_eq!(
            *cache.get_or_compute("b", hour, compute()).await.unwrap(),
            2,
            "b stays"
        );
        assert_eq!(
            *cache.get_or_compute("a", hour, compute()).await.unwrap(),
            4,
            "a was dropped"
        );
        let failed: Result<_, &str> = cache.get_or_compute("d", hour, async { Err("down") }).await;
        assert!(failed.is_err());
        assert_eq!(
            *cache.get_or_compute("d", hour, compute()).await.unwrap(),
            5,
            "errors are not cached"
        );
    }
}
