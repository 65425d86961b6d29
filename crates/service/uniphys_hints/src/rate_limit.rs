//! Fleet-wide rate limits: a token bucket per named limit.
//!
//! The bucket holds at most `per_minute` tokens and refills at `per_minute` tokens per minute,
//! continuously. It starts full, so a fresh limit lets exactly `per_minute` requests through at
//! once and then one more every `60 s / per_minute`. The Redis backend runs the same arithmetic
//! as [`TokenBucket::take`] inside one Lua script on the Redis clock.

use std::time::Duration;

use crate::error::{HintsError, HintsResult};

/// Milliseconds in the refill window.
pub(crate) const WINDOW_MS: u64 = 60_000;

/// A named limit shared by every process that uses the same name and key prefix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RateLimit {
    /// The limit's name, e.g. `lvlm` (part of the Redis key).
    pub name: String,
    /// Requests allowed per minute (also the burst size). Must be at least 1.
    pub per_minute: u32,
}

impl RateLimit {
    /// A limit of `per_minute` requests a minute under `name`.
    pub fn new(name: impl Into<String>, per_minute: u32) -> Self {
        Self {
            name: name.into(),
            per_minute,
        }
    }

    /// Checks that `n` tokens can ever be granted by this limit.
    pub(crate) fn validate(&self, n: u32) -> HintsResult<()> {
        if self.per_minute == 0 {
            return Err(HintsError::InvalidArgument(format!(
                "rate limit {} has per_minute = 0",
                self.name
            )));
        }
        if n == 0 || n > self.per_minute {
            return Err(HintsError::InvalidArgument(format!(
                "cannot take {n} tokens from rate limit {} (1..={} allowed)",
                self.name, self.per_minute
            )));
        }
        Ok(())
    }
}

/// The answer of [`crate::Hints::try_acquire`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RateDecision {
    /// The tokens were taken: go ahead.
    Allowed,
    /// Not enough tokens: nothing was taken; try again after this long (always > 0).
    RetryAfter(Duration),
}

/// The in-process token bucket (the Lua script keeps the same two numbers in a Redis hash).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TokenBucket {
    /// Tokens left, fractional.
    pub tokens: f64,
    /// When `tokens` was last brought up to date, in milliseconds.
    pub updated_at_ms: u64,
}

impl TokenBucket {
    /// A full bucket at `now_ms`.
    pub fn full(per_minute: u32, now_ms: u64) -> Self {
        Self {
            tokens: f64::from(per_minute),
            updated_at_ms: now_ms,
        }
    }

    /// Refills the bucket up to `now_ms`, then takes `n` tokens if there are that many.
    pub fn take(&mut self, per_minute: u32, n: u32, now_ms: u64) -> RateDecision {
        let capacity = f64::from(per_minute);
        if now_ms > self.updated_at_ms {
            let elapsed = (now_ms - self.updated_at_ms) as f64;
            self.tokens = (self.tokens + elapsed * capacity / WINDOW_MS as f64).min(capacity);
            self.updated_at_ms = now_ms;
        }
        // A bucket made with a larger limit than today's must not keep the surplus.
        self.tokens = self.tokens.min(capacity);
        let wanted = f64::from(n);
        if self.tokens >= wanted {
            self.tokens -= wanted;
            RateDecision::Allowed
        } else {
            let wait_ms = ((wanted - self.tokens) * WINDOW_MS as f64 / capacity).ceil();
            RateDecision::RetryAfter(Duration::from_millis((wait_ms as u64).max(1)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_bucket_allows_exactly_its_capacity_then_asks_to_wait() {
        let mut bucket = TokenBucket::full(3, 1_000);
        for _ in 0..3 {
            assert_eq!(bucket.take(3, 1, 1_000), RateDecision::Allowed);
        }
        assert_eq!(
            bucket.take(3, 1, 1_000),
            RateDecision::RetryAfter(Duration::from_millis(20_000))
        );
    }

    #[test]
    fn refills_continuously() {
        let mut bucket = TokenBucket::full(60, 0);
        assert_eq!(bucket.take(60, 60, 0), RateDecision::Allowed);
        assert!(
            matches!(bucket.take(60, 1, 500), RateDecision::RetryAfter(d) if d == Duration::from_millis(500))
        );
        assert_eq!(bucket.take(60, 1, 1_000), RateDecision::Allowed);
    }

    #[test]
    fn validate_rejects_impossible_requests() {
        assert!(RateLimit::new("x", 0).validate(1).is_err());
        assert!(RateLimit::new("x", 2).validate(3).is_err());
        assert!(RateLimit::new("x", 2).validate(0).is_err());
        assert!(RateLimit::new("x", 2).validate(2).is_ok());
    }
}
