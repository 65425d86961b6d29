//! The LVLM client's rate limiter over the fleet-wide token bucket in Redis
//! ([`uniphys_hints::Hints::try_acquire`]), so every worker of the fleet shares one request rate.
//!
//! Redis is a hint: when it cannot answer, the process falls back to a local bucket with the
//! same rate, so requests go on (the fleet may then exceed the limit by the number of workers).

use std::time::Duration;

use uniphys_hints::{Hints, RateDecision, RateLimit};
use uniphys_lvlm::{LocalTokenBucket, LvlmError, LvlmResult, RateLimiter};

/// Longest single wait before asking Redis again.
const MAX_WAIT: Duration = Duration::from_secs(5);

/// A [`RateLimiter`] backed by the fleet's Redis token bucket named `limit.name`.
pub struct FleetRateLimiter {
    hints: Hints,
    limit: RateLimit,
    runtime: tokio::runtime::Handle,
    fallback: LocalTokenBucket,
}

impl FleetRateLimiter {
    /// A limiter of `per_minute` requests a minute shared by every process using `name`.
    /// `runtime` runs the Redis calls; `acquire` must not be called from one of its async tasks.
    ///
    /// # Errors
    /// `per_minute` is 0.
    pub fn new(
        hints: Hints,
        name: &str,
        per_minute: u32,
        runtime: tokio::runtime::Handle,
    ) -> LvlmResult<Self> {
        // A second's worth of burst: when Redis goes away, workers do not each send a minute's.
        let fallback =
            LocalTokenBucket::new(f64::from(per_minute) / 60.0, (per_minute / 60).max(1))?;
        Ok(Self {
            hints,
            limit: RateLimit::new(name, per_minute),
            runtime,
            fallback,
        })
    }
}

impl RateLimiter for FleetRateLimiter {
    fn acquire(&self) -> LvlmResult<()> {
        loop {
            match self
                .runtime
                .block_on(self.hints.try_acquire(&self.limit, 1))
            {
                Ok(RateDecision::Allowed) => return Ok(()),
                Ok(RateDecision::RetryAfter(wait)) => std::thread::sleep(wait.min(MAX_WAIT)),
                Err(uniphys_hints::HintsError::InvalidArgument(reason)) => {
                    return Err(LvlmError::RateLimiter { reason });
                }
                // Redis is away: the local bucket keeps this process within the rate.
                Err(_) => return self.fallback.acquire(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use super::*;

    #[test]
    fn the_shared_bucket_spaces_requests_across_limiters() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let hints = Hints::local();
        // Two limiters (two workers) on one bucket of 120 a minute: a burst of 120, then one
        // every 0.5 s, whoever asks.
        let a =
            FleetRateLimiter::new(hints.clone(), "lvlm", 120, runtime.handle().clone()).unwrap();
        let b = FleetRateLimiter::new(hints, "lvlm", 120, runtime.handle().clone()).unwrap();
        for _ in 0..60 {
            a.acquire().unwrap();
            b.acquire().unwrap();
        }
        let start = Instant::now();
        a.acquire().unwrap();
        b.acquire().unwrap();
        let waited = start.elapsed();
        assert!(waited >= Duration::from_millis(900), "{waited:?}");
    }

    #[test]
    fn a_zero_rate_is_refused() {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        assert!(
            FleetRateLimiter::new(Hints::local(), "lvlm", 0, runtime.handle().clone()).is_err()
        );
    }
}
