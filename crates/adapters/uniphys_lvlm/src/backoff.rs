use std::time::Duration;

/// Wait after failed attempt `attempt` (1-based) of the request with digest `digest`.
///
/// With a server's `Retry-After`, that wait, capped at `max`. Otherwise the exponential
/// `initial * 2^(attempt - 1)`, capped at `max`, scaled by a jitter factor in [0.5, 1) derived
/// from the digest and the attempt: deterministic for a request, yet different requests that
/// failed together do not retry in lockstep.
#[must_use]
pub fn backoff_delay(
    initial: Duration,
    max: Duration,
    attempt: u32,
    digest: &str,
    retry_after: Option<Duration>,
) -> Duration {
    if let Some(wait) = retry_after {
        return wait.min(max);
    }
    let factor = 2u32.saturating_pow(attempt.saturating_sub(1).min(30));
    let base = initial.saturating_mul(factor).min(max);
    base.mul_f64(0.5 + 0.5 * unit_jitter(digest, attempt))
}

/// A number in [0, 1) from `digest` and `attempt` (FNV-1a, then the SplitMix64 finaliser).
fn unit_jitter(digest: &str, attempt: u32) -> f64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in digest.bytes().chain(attempt.to_le_bytes()) {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash = (hash ^ (hash >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    hash = (hash ^ (hash >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    hash ^= hash >> 31;
    (hash >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn exponential_with_jitter_within_half_to_full_and_capped() {
        for attempt in 1..=8 {
            let delay = backoff_delay(MS * 100, MS * 1000, attempt, "abc", None);
            let base = (MS * 100 * 2u32.pow(attempt - 1)).min(MS * 1000);
            assert!(
                delay >= base / 2 && delay < base,
                "attempt {attempt}: {delay:?}"
            );
        }
    }

    #[test]
    fn deterministic_per_digest_and_attempt_but_spread_across_requests() {
        let one = backoff_delay(MS * 1000, MS * 60_000, 2, "d1", None);
        assert_eq!(one, backoff_delay(MS * 1000, MS * 60_000, 2, "d1", None));
        let delays: std::collections::BTreeSet<Duration> = (0..20)
            .map(|i| backoff_delay(MS * 1000, MS * 60_000, 2, &format!("d{i}"), None))
            .collect();
        assert!(delays.len() >= 15, "{delays:?}");
    }

    #[test]
    fn retry_after_is_honoured_and_capped() {
        let max = Duration::from_secs(30);
        let wait = Some(Duration::from_secs(7));
        assert_eq!(backoff_delay(MS, max, 1, "d", wait), Duration::from_secs(7));
        let long = Some(Duration::from_secs(600));
        assert_eq!(backoff_delay(MS, max, 1, "d", long), max);
    }

    #[test]
    fn jitter_is_in_the_unit_interval() {
        for attempt in 0..200 {
            let u = unit_jitter("some-digest", attempt);
            assert!((0.0..1.0).contains(&u), "{u}");
        }
    }
}
