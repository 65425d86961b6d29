//! Key and channel names under one prefix: `{prefix}:{kind}:{name}`.
//!
//! Everything this crate writes lives under the prefix, so [`crate::Hints::clear`] (or an operator's
//! `SCAN MATCH prefix:*`) finds all of it, and tests use a unique prefix each.

/// The names of one deployment's keys and channels.
#[derive(Debug, Clone)]
pub(crate) struct Keys {
    prefix: String,
}

impl Keys {
    pub fn new(prefix: &str) -> Self {
        Self {
            prefix: prefix.trim_end_matches(':').to_owned(),
        }
    }

    /// Pub/sub channel a stage's doorbell listens on.
    pub fn ring(&self, stage: &str) -> String {
        format!("{}:ring:{stage}", self.prefix)
    }

    /// Pub/sub channel for application events (server-sent events).
    pub fn events(&self, channel: &str) -> String {
        format!("{}:events:{channel}", self.prefix)
    }

    /// Hash holding one rate limit's token bucket.
    pub fn rate(&self, name: &str) -> String {
        format!("{}:rate:{name}", self.prefix)
    }

    /// Sorted set of one slot pool's holders, scored by expiry (Unix ms, Redis clock).
    pub fn slots(&self, pool: &str) -> String {
        format!("{}:slots:{pool}", self.prefix)
    }

    /// Hash of one job's progress, field = stage, value = JSON [`crate::Progress`].
    pub fn progress(&self, job_id: i64) -> String {
        format!("{}:progress:{job_id}", self.prefix)
    }

    /// `SCAN MATCH` pattern for every key under the prefix.
    pub fn all_pattern(&self) -> String {
        let mut pattern = String::with_capacity(self.prefix.len() + 2);
        for c in self.prefix.chars() {
            if matches!(c, '*' | '?' | '[' | ']' | '\\') {
                pattern.push('\\');
            }
            pattern.push(c);
        }
        pattern.push_str(":*");
        pattern
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_prefixed_and_distinct() {
        let keys = Keys::new("uniphys:");
        assert_eq!(keys.ring("ground"), "uniphys:ring:ground");
        assert_eq!(keys.progress(7), "uniphys:progress:7");
        assert_ne!(keys.ring("a"), keys.events("a"));
        assert_eq!(keys.all_pattern(), "uniphys:*");
        assert_eq!(Keys::new("t[1]*").all_pattern(), "t\\[1\\]\\*:*");
    }
}
