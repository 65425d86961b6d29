use std::sync::{Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::{UniPhysGenError, UniPhysGenResult};

/// A limit on concurrent model-server requests (GPU slots). The client takes a slot around each
/// HTTP attempt and gives it back afterwards. [`LocalSlots`] limits one process; a limiter
/// shared between workers (the queue's Redis limiter) implements the same trait.
pub trait SlotLimiter: Send + Sync {
    /// Takes a slot, waiting at most `wait` for one to be free.
    ///
    /// # Errors
    /// [`UniPhysGenError::NoSlot`] if none became free in time.
    fn acquire(&self, wait: Duration) -> UniPhysGenResult<()>;

    /// Gives back a slot taken with [`SlotLimiter::acquire`].
    fn release(&self);
}

/// An in-process counting semaphore of `capacity` slots.
#[derive(Debug)]
pub struct LocalSlots {
    capacity: usize,
    in_use: Mutex<usize>,
    freed: Condvar,
}

impl LocalSlots {
    /// A limiter with `capacity` slots (at least 1).
    #[must_use]
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity: capacity.max(1),
            in_use: Mutex::new(0),
            freed: Condvar::new(),
        }
    }

    /// Slots currently taken.
    #[must_use]
    pub fn in_use(&self) -> usize {
        *self.in_use.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

impl SlotLimiter for LocalSlots {
    fn acquire(&self, wait: Duration) -> UniPhysGenResult<()> {
        let deadline = Instant::now() + wait;
        let mut in_use = self.in_use.lock().unwrap_or_else(PoisonError::into_inner);
        while *in_use >= self.capacity {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(UniPhysGenError::NoSlot { waited: wait });
            }
            in_use = self
                .freed
                .wait_timeout(in_use, left)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
        *in_use += 1;
        Ok(())
    }

    fn release(&self) {
        let mut in_use = self.in_use.lock().unwrap_or_else(PoisonError::into_inner);
        *in_use = in_use.saturating_sub(1);
        self.freed.notify_one();
    }
}

/// Holds a slot until dropped.
pub(crate) struct SlotGuard<'a> {
    limiter: &'a dyn SlotLimiter,
}

impl<'a> SlotGuard<'a> {
    pub(crate) fn take(limiter: &'a dyn SlotLimiter, wait: Duration) -> UniPhysGenResult<Self> {
        limiter.acquire(wait)?;
        Ok(Self { limiter })
    }
}

impl Drop for SlotGuard<'_> {
    fn drop(&mut self) {
        self.limiter.release();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn a_full_limiter_refuses_after_the_wait_and_accepts_after_a_release() {
        let slots = LocalSlots::new(2);
        slots.acquire(Duration::ZERO).unwrap();
        slots.acquire(Duration::ZERO).unwrap();
        assert_eq!(slots.in_use(), 2);
        let error = slots.acquire(Duration::from_millis(20)).unwrap_err();
        assert!(error.to_string().contains("GPU slot"), "{error}");
        slots.release();
        slots.acquire(Duration::ZERO).unwrap();
        assert_eq!(slots.in_use(), 2);
    }

    #[test]
    fn a_waiting_acquire_wakes_when_another_thread_releases() {
        let slots = Arc::new(LocalSlots::new(1));
        slots.acquire(Duration::ZERO).unwrap();
        let other = Arc::clone(&slots);
        let releaser = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(30));
            other.release();
        });
        slots.acquire(Duration::from_secs(5)).unwrap();
        releaser.join().unwrap();
        assert_eq!(slots.in_use(), 1);
    }

    #[test]
    fn the_guard_gives_its_slot_back_on_drop() {
        let slots = LocalSlots::new(1);
        {
            let _guard = SlotGuard::take(&slots, Duration::ZERO).unwrap();
            assert_eq!(slots.in_use(), 1);
        }
        assert_eq!(slots.in_use(), 0);
    }
}
