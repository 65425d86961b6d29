use std::sync::{Condvar, Mutex, PoisonError};

/// A counting semaphore: at most `capacity` holders of a [`Permit`] at once.
#[derive(Debug)]
pub struct Permits {
    capacity: usize,
    in_use: Mutex<usize>,
    freed: Condvar,
}

/// A held permit, given back on drop.
#[derive(Debug)]
pub struct Permit<'a> {
    permits: &'a Permits,
}

impl Permits {
    /// A semaphore of `capacity` permits (at least 1).
    #[must_use]
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity: capacity.max(1),
            in_use: Mutex::new(0),
            freed: Condvar::new(),
        }
    }

    /// The number of permits.
    #[must_use]
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Permits currently held.
    #[must_use]
    pub fn in_use(&self) -> usize {
        *self.in_use.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Blocks until a permit is free and takes it.
    pub fn acquire(&self) -> Permit<'_> {
        let mut in_use = self.in_use.lock().unwrap_or_else(PoisonError::into_inner);
        while *in_use >= self.capacity {
            in_use = self
                .freed
                .wait(in_use)
                .unwrap_or_else(PoisonError::into_inner);
        }
        *in_use += 1;
        Permit { permits: self }
    }
}

impl Drop for Permit<'_> {
    fn drop(&mut self) {
        let mut in_use = self
            .permits
            .in_use
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        *in_use = in_use.saturating_sub(1);
        self.permits.freed.notify_one();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn never_more_holders_than_capacity() {
        let permits = Arc::new(Permits::new(3));
        let holding = Arc::new(AtomicUsize::new(0));
        let peak = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..12)
            .map(|_| {
                let (permits, holding, peak) = (
                    Arc::clone(&permits),
                    Arc::clone(&holding),
                    Arc::clone(&peak),
                );
                std::thread::spawn(move || {
                    for _ in 0..20 {
                        let _permit = permits.acquire();
                        let now = holding.fetch_add(1, Ordering::SeqCst) + 1;
                        peak.fetch_max(now, Ordering::SeqCst);
                        std::thread::yield_now();
                        holding.fetch_sub(1, Ordering::SeqCst);
                    }
                })
            })
            .collect();
        for thread in threads {
            thread.join().unwrap();
        }
        assert!(peak.load(Ordering::SeqCst) <= 3);
        assert_eq!(permits.in_use(), 0);
    }

    #[test]
    fn zero_capacity_means_one() {
        let permits = Permits::new(0);
        assert_eq!(permits.capacity(), 1);
        let permit = permits.acquire();
        assert_eq!(permits.in_use(), 1);
        drop(permit);
        assert_eq!(permits.in_use(), 0);
    }
}
