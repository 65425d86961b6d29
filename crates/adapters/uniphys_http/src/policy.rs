use std::time::Duration;

use crate::{HttpError, HttpResult, unit_jitter};

/// How a request is retried: attempts, exponential backoff with jitter, the cap that also
/// bounds a server's `Retry-After`, and an optional deadline over all attempts and waits.
#[derive(Debug, Clone, PartialEq)]
pub struct RetryPolicy {
    /// Attempts per request, the first included (at least 1).
    pub max_attempts: u32,
    /// Backoff before the second attempt; doubled for each further one.
    pub base_delay: Duration,
    /// Longest wait between attempts; also caps a server's `Retry-After`.
    pub max_delay: Duration,
    /// Share of the backoff that jitter may take off, in [0, 1]: the wait after attempt `n` is
    /// in `[(1 - jitter_fraction) * d, d)` with `d = min(base_delay * 2^(n-1), max_delay)`
    /// (exactly `d` when 0).
    pub jitter_fraction: f64,
    /// Limit on the whole request, every attempt and wait included; no attempt starts (and no
    /// wait begins) that the deadline would cut off, and an attempt's timeout is cut to the
    /// time left. `None`: attempts alone bound it.
    pub deadline: Option<Duration>,
}

impl Default for RetryPolicy {
    /// 4 attempts, 0.5 s doubling to at most 30 s, half of it jitter, no deadline.
    fn default() -> Self {
        Self {
            max_attempts: 4,
            base_delay: Duration::from_millis(500),
            max_delay: Duration::from_secs(30),
            jitter_fraction: 0.5,
            deadline: None,
        }
    }
}

impl RetryPolicy {
    /// `max_attempts` with backoff from `base_delay` doubling to at most `max_delay`, half of
    /// each backoff jitter, no deadline: the policy the model-service clients build from their
    /// settings.
    #[must_use]
    pub fn exponential(max_attempts: u32, base_delay: Duration, max_delay: Duration) -> Self {
        Self {
            max_attempts,
            base_delay,
            max_delay,
            ..Self::default()
        }
    }

    /// Checks the settings.
    ///
    /// # Errors
    /// [`HttpError::InvalidOption`] for no attempts, a jitter fraction outside [0, 1] or a zero
    /// deadline.
    pub fn validate(&self) -> HttpResult<()> {
        let invalid = |name, value: String, expected| {
            Err(HttpError::InvalidOption {
                name,
                value,
                expected,
            })
        };
        if self.max_attempts == 0 {
            return invalid("max_attempts", "0".to_owned(), "at least 1");
        }
        if !(0.0..=1.0).contains(&self.jitter_fraction) {
            return invalid(
                "jitter_fraction",
                self.jitter_fraction.to_string(),
                "a number in [0, 1]",
            );
        }
        if self.deadline == Some(Duration::ZERO) {
            return invalid("deadline", "0 s".to_owned(), "more than zero, or none");
        }
        Ok(())
    }

    /// The backoff ceiling after failed attempt `attempt` (1-based), before jitter:
    /// `base_delay * 2^(attempt - 1)`, at most `max_delay`.
    #[must_use]
    pub fn backoff_ceiling(&self, attempt: u32) -> Duration {
        let factor = 2u32.saturating_pow(attempt.saturating_sub(1).min(30));
        self.base_delay.saturating_mul(factor).min(self.max_delay)
    }

    /// The wait after failed attempt `attempt` (1-based) of the request identified by
    /// `jitter_key`: the server's `Retry-After` capped at `max_delay` (no jitter: the server
    /// chose it), else the backoff ceiling less up to `jitter_fraction` of it.
    #[must_use]
    pub fn delay(
        &self,
        attempt: u32,
        jitter_key: &[u8],
        retry_after: Option<Duration>,
    ) -> Duration {
        if let Some(wait) = retry_after {
            return wait.min(self.max_delay);
        }
        let ceiling = self.backoff_ceiling(attempt);
        let jitter = self.jitter_fraction.clamp(0.0, 1.0);
        ceiling.mul_f64(1.0 - jitter + jitter * unit_jitter(jitter_key, attempt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    fn policy() -> RetryPolicy {
        RetryPolicy {
            base_delay: MS * 100,
            max_delay: MS * 1000,
            ..RetryPolicy::default()
        }
    }

    #[test]
    fn the_backoff_doubles_and_is_capped() {
        let policy = policy();
        assert_eq!(policy.backoff_ceiling(1), MS * 100);
        assert_eq!(policy.backoff_ceiling(3), MS * 400);
        assert_eq!(policy.backoff_ceiling(5), MS * 1000);
        assert_eq!(policy.backoff_ceiling(u32::MAX), MS * 1000);
    }

    #[test]
    fn the_jittered_wait_stays_within_its_bounds() {
        let policy = policy();
        for attempt in 1..=8 {
            for key in 0..50u32 {
                let delay = policy.delay(attempt, &key.to_le_bytes(), None);
                let ceiling = policy.backoff_ceiling(attempt);
                assert!(
                    delay >= ceiling / 2 && delay < ceiling,
                    "attempt {attempt}: {delay:?} of {ceiling:?}"
                );
            }
        }
        let exact = RetryPolicy {
            jitter_fraction: 0.0,
            ..policy
        };
        assert_eq!(exact.delay(3, b"k", None), MS * 400);
    }

    #[test]
    fn jitter_spreads_requests_that_failed_together() {
        let policy = policy();
        let delays: std::collections::BTreeSet<Duration> = (0..20u32)
            .map(|key| policy.delay(2, &key.to_le_bytes(), None))
            .collect();
        assert!(delays.len() >= 15, "{delays:?}");
    }

    #[test]
    fn retry_after_replaces_the_backoff_and_is_capped() {
        let policy = policy();
        assert_eq!(policy.delay(1, b"k", Some(MS * 700)), MS * 700);
        assert_eq!(policy.delay(4, b"k", Some(Duration::ZERO)), Duration::ZERO);
        assert_eq!(
            policy.delay(1, b"k", Some(Duration::from_secs(60))),
            MS * 1000
        );
        assert_eq!(policy.delay(3, b"k", Some(MS * 70)), MS * 70);
    }

    #[test]
    fn bad_settings_are_named() {
        for (policy, name) in [
            (
                RetryPolicy {
                    max_attempts: 0,
                    ..RetryPolicy::default()
                },
                "max_attempts",
            ),
            (
                RetryPolicy {
                    jitter_fraction: 1.5,
                    ..RetryPolicy::default()
                },
                "jitter_fraction",
            ),
            (
                RetryPolicy {
                    deadline: Some(Duration::ZERO),
                    ..RetryPolicy::default()
                },
                "deadline",
            ),
        ] {
            let message = policy.validate().unwrap_err().to_string();
            assert!(message.contains(name), "{message}");
        }
        assert!(RetryPolicy::default().validate().is_ok());
    }
}
