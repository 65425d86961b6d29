use std::time::Duration;

use uniphys_http::RetryPolicy;

/// Wait after failed attempt `attempt` (1-based) of the request with digest `digest`, by the
/// shared policy (`uniphys_http::RetryPolicy` with half of each backoff jitter).
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
    RetryPolicy::exponential(1, initial, max).delay(attempt, digest.as_bytes(), retry_after)
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
}
