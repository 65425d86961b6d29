//! Exponential backoff with jitter between attempts of a failed stage run.

use std::collections::hash_map::RandomState;
use std::hash::BuildHasher;
use std::time::Duration;

/// Delay before attempt `n + 1` after attempt `n` failed: `base * 2^(n-1)`, capped at `max`,
/// then "equal jitter": a uniformly random point in the upper half of that delay, so retries of
/// runs that failed together spread out while each still waits at least half the nominal delay.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RetryPolicy {
    /// Nominal delay after the first failed attempt.
    pub base_delay: Duration,
    /// Cap on the nominal delay.
    pub max_delay: Duration,
}

impl Default for RetryPolicy {
    /// 5 s, 10 s, 20 s, … capped at 10 min (before jitter).
    fn default() -> Self {
        Self {
            base_delay: Duration::from_secs(5),
            max_delay: Duration::from_secs(600),
        }
    }
}

impl RetryPolicy {
    /// The nominal (unjittered) delay after failed attempt `attempt` (1-based).
    #[must_use]
    pub fn nominal_delay(&self, attempt: u32) -> Duration {
        let doublings = attempt.saturating_sub(1).min(31);
        self.base_delay
            .saturating_mul(1_u32 << doublings)
            .min(self.max_delay)
    }

    /// The delay to wait after failed attempt `attempt`, jittered with `unit` in `[0, 1)`.
    #[must_use]
    pub fn delay_with_jitter(&self, attempt: u32, unit: f64) -> Duration {
        let nominal = self.nominal_delay(attempt);
        let half = nominal / 2;
        half + half.mul_f64(unit.clamp(0.0, 1.0))
    }

    /// The delay to wait after failed attempt `attempt`, with fresh randomness.
    #[must_use]
    pub fn delay(&self, attempt: u32) -> Duration {
        self.delay_with_jitter(attempt, random_unit())
    }
}

/// A random number in `[0, 1)` from std's per-instance random hasher keys (no RNG dependency;
/// jitter needs spread, not cryptographic quality).
fn random_unit() -> f64 {
    let bits = RandomState::new().hash_one(0_u8) >> 11;
    #[expect(
        clippy::cast_precision_loss,
        reason = "53-bit value fits an f64 mantissa exactly"
    )]
    let unit = bits as f64 / (1_u64 << 53) as f64;
    unit
}

#[cfg(test)]
mod tests {
    use super::*;

    const POLICY: RetryPolicy = RetryPolicy {
        base_delay: Duration::from_secs(2),
        max_delay: Duration::from_secs(60),
    };

    #[test]
    fn nominal_delay_doubles_per_attempt_up_to_the_cap() {
        let secs: Vec<u64> = (1..=7).map(|a| POLICY.nominal_delay(a).as_secs()).collect();
        assert_eq!(secs, [2, 4, 8, 16, 32, 60, 60]);
        assert_eq!(POLICY.nominal_delay(1000), Duration::from_secs(60));
    }

    #[test]
    fn jitter_stays_in_the_upper_half_of_the_nominal_delay() {
        assert_eq!(POLICY.delay_with_jitter(3, 0.0), Duration::from_secs(4));
        assert_eq!(POLICY.delay_with_jitter(3, 1.0), Duration::from_secs(8));
        for _ in 0..100 {
            let d = POLICY.delay(3);
            assert!(
                d >= Duration::from_secs(4) && d <= Duration::from_secs(8),
                "{d:?}"
            );
        }
    }

    #[test]
    fn random_jitter_spreads() {
        let draws: Vec<u128> = (0..50).map(|_| POLICY.delay(6).as_millis()).collect();
        let distinct: std::collections::BTreeSet<_> = draws.iter().collect();
        assert!(distinct.len() > 40, "{draws:?}");
    }
}
