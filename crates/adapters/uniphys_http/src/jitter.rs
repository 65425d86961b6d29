/// A number in [0, 1) from `key` and `attempt` (FNV-1a, then the SplitMix64 finaliser):
/// deterministic for a request, yet requests with different keys that failed together do not
/// retry in lockstep.
#[must_use]
pub fn unit_jitter(key: &[u8], attempt: u32) -> f64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in key.iter().copied().chain(attempt.to_le_bytes()) {
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

    #[test]
    fn jitter_is_in_the_unit_interval_and_spread() {
        let mut values = Vec::new();
        for attempt in 0..200 {
            let u = unit_jitter(b"some-digest", attempt);
            assert!((0.0..1.0).contains(&u), "{u}");
            values.push(u);
        }
        let low = values.iter().filter(|u| **u < 0.5).count();
        assert!((60..=140).contains(&low), "{low} of 200 below 0.5");
    }

    #[test]
    fn jitter_is_deterministic_per_key_and_attempt() {
        assert_eq!(unit_jitter(b"a", 3), unit_jitter(b"a", 3));
        assert_ne!(unit_jitter(b"a", 3), unit_jitter(b"b", 3));
        assert_ne!(unit_jitter(b"a", 3), unit_jitter(b"a", 4));
    }
}
