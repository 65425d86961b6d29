use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::{LvlmError, LvlmResult};

/// A limit on the rate of requests. The client calls [`RateLimiter::acquire`] before each HTTP
/// attempt (retries included). The worker implements it over the fleet-wide Redis limiter.
pub trait RateLimiter: Send + Sync {
    /// Blocks until a request may be sent.
    ///
    /// # Errors
    /// [`LvlmError::RateLimiter`] if the limiter cannot decide (the request is not sent).
    fn acquire(&self) -> LvlmResult<()>;
}

/// No rate limit.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoRateLimit;

impl RateLimiter for NoRateLimit {
    fn acquire(&self) -> LvlmResult<()> {
        Ok(())
    }
}

/// An in-process token bucket: `burst` requests at once, refilled at `requests_per_sec`.
#[derive(Debug)]
pub struct LocalTokenBucket {
    requests_per_sec: f64,
    burst: f64,
    state: Mutex<Bucket>,
}

#[derive(Debug, Clone, Copy)]
struct Bucket {
    tokens: f64,
    refilled_at: Instant,
}

impl LocalTokenBucket {
    /// A full bucket of `burst` tokens refilled at `requests_per_sec`.
    ///
    /// # Errors
    /// [`LvlmError::InvalidConfig`] for a rate that is not positive and finite, or a zero burst.
    pub fn new(requests_per_sec: f64, burst: u32) -> LvlmResult<Self> {
        if !(requests_per_sec.is_finite() && requests_per_sec > 0.0) {
            return Err(LvlmError::InvalidConfig {
                name: "requests_per_sec",
                value: requests_per_sec.to_string(),
                expected: "a positive number",
            });
        }
        if burst == 0 {
            return Err(LvlmError::InvalidConfig {
                name: "burst",
                value: "0".to_owned(),
                expected: "at least 1",
            });
        }
        Ok(Self {
            requests_per_sec,
            burst: f64::from(burst),
            state: Mutex::new(Bucket {
                tokens: f64::from(burst),
                refilled_at: Instant::now(),
            }),
        })
    }

    /// Takes a token if one is available at `now`; otherwise returns how long until one is.
    fn try_take(&self, now: Instant) -> Result<(), Duration> {
        let mut bucket = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let elapsed_secs = now
            .saturating_duration_since(bucket.refilled_at)
            .as_secs_f64();
        bucket.tokens = (bucket.tokens + elapsed_secs * self.requests_per_sec).min(self.burst);
        bucket.refilled_at = bucket.refilled_at.max(now);
        if bucket.tokens >= 1.0 {
            bucket.tokens -= 1.0;
            Ok(())
        } else {
            let missing = 1.0 - bucket.tokens;
            Err(Duration::from_secs_f64(missing / self.requests_per_sec))
        }
    }
}

impl RateLimiter for LocalTokenBucket {
    fn acquire(&self) -> LvlmResult<()> {
        loop {
            match self.try_take(Instant::now()) {
                Ok(()) => return Ok(()),
                Err(wait) => std::thread::sleep(wait.max(Duration::from_micros(100))),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn burst_then_one_token_per_interval() {
        let bucket = LocalTokenBucket::new(10.0, 2).unwrap();
        let start = bucket.state.lock().unwrap().refilled_at;
        assert_eq!(bucket.try_take(start), Ok(()));
        assert_eq!(bucket.try_take(start), Ok(()));
        let wait = bucket.try_take(start).unwrap_err();
        assert!((wait.as_secs_f64() - 0.1).abs() < 1e-9, "{wait:?}");
        let half = start + Duration::from_millis(50);
        let wait = bucket.try_take(half).unwrap_err();
        assert!((wait.as_secs_f64() - 0.05).abs() < 1e-9, "{wait:?}");
        assert_eq!(bucket.try_take(start + Duration::from_millis(100)), Ok(()));
        // A long pause refills at most `burst` tokens.
        let later = start + Duration::from_secs(60);
        assert_eq!(bucket.try_take(later), Ok(()));
        assert_eq!(bucket.try_take(later), Ok(()));
        assert!(bucket.try_take(later).is_err());
    }

    #[test]
    fn invalid_rates_are_refused() {
        assert!(LocalTokenBucket::new(0.0, 1).is_err());
        assert!(LocalTokenBucket::new(f64::INFINITY, 1).is_err());
        assert!(LocalTokenBucket::new(1.0, 0).is_err());
    }

    #[test]
    fn acquire_blocks_until_a_token_is_refilled() {
        // 20 a second, burst 1: the second token exists only 50 ms after the first was taken.
        let bucket = LocalTokenBucket::new(20.0, 1).unwrap();
        bucket.acquire().unwrap();
        let start = std::time::Instant::now();
        bucket.acquire().unwrap();
        let waited = start.elapsed();
        assert!(waited >= Duration::from_millis(40), "{waited:?}");
        assert!(bucket.state.lock().unwrap().tokens < 1.0);
    }
}
