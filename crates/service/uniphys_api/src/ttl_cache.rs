//! A map of values that expire: what the dashboard's per-tenant answers are cached in, so many
//! viewers polling the same tenant (or batch) cost one query per interval. While one caller
//! recomputes a stale value, the others get the stale one instead of waiting or piling on; while
//! one computes a value never computed before, the others wait for it.

use std::collections::HashMap;
use std::future::Future;
use std::hash::Hash;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use tokio::sync::Notify;

/// One key's value, or its first computation in flight.
#[derive(Debug)]
struct Entry<V> {
    taken: Instant,
    /// `None` until the first computation succeeds.
    value: Option<Arc<V>>,
    /// A caller is (re)computing it.
    refreshing: bool,
    /// Woken when a computation ends, however it ends.
    done: Arc<Notify>,
}

/// Values by key, each kept for the `ttl` given when it is read.
#[derive(Debug)]
pub(crate) struct TtlCache<K, V> {
    /// Never held across an await.
    entries: Mutex<HashMap<K, Entry<V>>>,
    /// Entries beyond this many are dropped, oldest first, when one is added.
    capacity: usize,
}

/// What a caller found under the lock.
enum Found<V> {
    Value(Arc<V>),
    /// Another caller computes the first value: wait for it, then look again.
    Wait(tokio::sync::futures::OwnedNotified),
    /// This caller computes.
    Compute,
}

/// Ends a claimed computation if its future is dropped (a client that hung up): the claim is
/// released and waiters are woken, so the key is never left refreshing forever.
struct Claim<'a, K: Eq + Hash + Clone, V> {
    cache: &'a TtlCache<K, V>,
    key: Option<K>,
}

impl<K: Eq + Hash + Clone, V> Drop for Claim<'_, K, V> {
    fn drop(&mut self) {
        if let Some(key) = self.key.take() {
            self.cache.release(&key);
        }
    }
}

impl<K: Eq + Hash + Clone, V> TtlCache<K, V> {
    pub(crate) fn new(capacity: usize) -> Self {
        Self {
            entries: Mutex::new(HashMap::new()),
            capacity: capacity.max(1),
        }
    }

    fn lock(&self) -> MutexGuard<'_, HashMap<K, Entry<V>>> {
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The value of `key` if computed less than `ttl` ago; else, when another caller is already
    /// recomputing it, the stale value; else `compute()`'s (cached on success). A key with no
    /// value yet is computed by one caller while the others wait. The map is not locked while
    /// computing, so one key's query never waits for another's.
    pub(crate) async fn get_or_compute<E, F>(
        &self,
        key: K,
        ttl: Duration,
        compute: F,
    ) -> Result<Arc<V>, E>
    where
        F: Future<Output = Result<V, E>>,
    {
        loop {
            match self.find(&key, ttl) {
                Found::Value(value) => return Ok(value),
                Found::Wait(done) => done.await,
                Found::Compute => break,
            }
        }
        let mut claim = Claim {
            cache: self,
            key: Some(key),
        };
        let computed = compute.await;
        let key = claim.key.take().expect("claimed once");
        match computed {
            Ok(value) => Ok(self.store(key, value)),
            Err(e) => {
                self.release(&key);
                Err(e)
            }
        }
    }

    fn find(&self, key: &K, ttl: Duration) -> Found<V> {
        let mut entries = self.lock();
        let Some(entry) = entries.get_mut(key) else {
            entries.insert(
                key.clone(),
                Entry {
                    taken: Instant::now(),
                    value: None,
                    refreshing: true,
                    done: Arc::default(),
                },
            );
            return Found::Compute;
        };
        match &entry.value {
            Some(value) if entry.taken.elapsed() < ttl || entry.refreshing => {
                Found::Value(Arc::clone(value))
            }
            None if entry.refreshing => Found::Wait(Arc::clone(&entry.done).notified_owned()),
            _ => {
                entry.refreshing = true;
                Found::Compute
            }
        }
    }

    /// Ends a computation that produced nothing: the stale value stays, a key never computed
    /// goes, and waiters look again.
    fn release(&self, key: &K) {
        let mut entries = self.lock();
        let Some(entry) = entries.get_mut(key) else {
            return;
        };
        entry.refreshing = false;
        entry.done.notify_waiters();
        if entry.value.is_none() {
            entries.remove(key);
        }
    }

    fn store(&self, key: K, value: V) -> Arc<V> {
        let value = Arc::new(value);
        let mut entries = self.lock();
        let computed = entries.get(&key).is_some_and(|e| e.value.is_some());
        if !computed && entries.values().filter(|e| e.value.is_some()).count() >= self.capacity {
            let oldest = entries
                .iter()
                .filter(|(_, e)| e.value.is_some())
                .min_by_key(|(_, e)| e.taken)
                .map(|(k, _)| k.clone());
            if let Some(oldest) = oldest {
                entries.remove(&oldest);
            }
        }
        let done = entries
            .get(&key)
            .map_or_else(Arc::default, |e| Arc::clone(&e.done));
        done.notify_waiters();
        entries.insert(
            key,
            Entry {
                taken: Instant::now(),
                value: Some(Arc::clone(&value)),
                refreshing: false,
                done,
            },
        );
        value
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

    #[tokio::test]
    async fn a_value_never_computed_is_computed_once_while_the_others_wait() {
        let cache: TtlCache<&str, u32> = TtlCache::new(4);
        let hour = Duration::from_secs(3600);
        let calls = AtomicU32::new(0);
        let release = Notify::new();
        let first = cache.get_or_compute("k", hour, async {
            calls.fetch_add(1, Ordering::SeqCst);
            release.notified().await;
            Ok::<_, ()>(1)
        });
        let second = async {
            tokio::task::yield_now().await;
            let waiting = cache.get_or_compute("k", hour, async {
                calls.fetch_add(1, Ordering::SeqCst);
                Ok::<_, ()>(2)
            });
            let (value, ()) = tokio::join!(waiting, async {
                tokio::task::yield_now().await;
                release.notify_one();
            });
            value
        };
        let (first, second) = tokio::join!(first, second);
        assert_eq!(*first.unwrap(), 1);
        assert_eq!(
            *second.unwrap(),
            1,
            "the second caller got the first's value"
        );
        assert_eq!(calls.load(Ordering::SeqCst), 1, "computed once");
    }

    #[tokio::test]
    async fn a_computation_dropped_midway_leaves_the_key_to_the_next_caller() {
        let cache: TtlCache<&str, u32> = TtlCache::new(4);
        let hour = Duration::from_secs(3600);
        let never = cache.get_or_compute("k", hour, std::future::pending::<Result<u32, ()>>());
        let dropped = tokio::time::timeout(Duration::from_millis(10), never).await;
        assert!(dropped.is_err(), "the first computation never ends");
        let next = cache
            .get_or_compute("k", hour, async { Ok::<_, ()>(7) })
            .await
            .unwrap();
        assert_eq!(*next, 7, "computed again, not left waiting");

        let stale = cache.get_or_compute(
            "k",
            Duration::ZERO,
            std::future::pending::<Result<u32, ()>>(),
        );
        assert!(
            tokio::time::timeout(Duration::from_millis(10), stale)
                .await
                .is_err()
        );
        let refreshed = cache
            .get_or_compute("k", Duration::ZERO, async { Ok::<_, ()>(8) })
            .await
            .unwrap();
        assert_eq!(
            *refreshed, 8,
            "a dropped refresh does not freeze the stale value"
        );
    }
}
