//! The in-process implementation for embedded mode (one process runs API and workers): the
//! same behaviour as Redis, with a broadcast channel as the pub/sub bus and maps under mutexes.
//! Nothing here crosses a process boundary.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use tokio::sync::broadcast;

use crate::doorbell::{self, Doorbell, EventStream, Source};
use crate::hints::HintsOptions;
use crate::keys::Keys;
use crate::progress::Progress;
use crate::rate_limit::{RateDecision, RateLimit, TokenBucket};

/// Messages the bus keeps for a slow subscriber before it lags.
const BUS_CAPACITY: usize = 1024;

/// One job's stored progress.
#[derive(Debug)]
struct JobProgress {
    expires_at: Instant,
    stages: BTreeMap<String, Progress>,
}

/// What the local backend remembers; all of it is lost with the process, like a flushed Redis.
#[derive(Debug, Default)]
struct State {
    buckets: BTreeMap<String, TokenBucket>,
    /// Pool → holder → slot expiry.
    slots: BTreeMap<String, BTreeMap<String, Instant>>,
    progress: BTreeMap<i64, JobProgress>,
}

/// In-process hints.
pub(crate) struct LocalHints {
    bus: broadcast::Sender<(Arc<str>, Arc<str>)>,
    keys: Keys,
    options: HintsOptions,
    started: Instant,
    state: Mutex<State>,
}

impl LocalHints {
    pub fn new(options: HintsOptions) -> Self {
        let (bus, _) = broadcast::channel(BUS_CAPACITY);
        Self {
            bus,
            keys: Keys::new("local"),
            options,
            started: Instant::now(),
            state: Mutex::new(State::default()),
        }
    }

    fn state(&self) -> MutexGuard<'_, State> {
        // The state is a cache of hints: a panic elsewhere leaves it usable.
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn now_ms(&self) -> u64 {
        u64::try_from(self.started.elapsed().as_millis()).unwrap_or(u64::MAX)
    }

    fn publish(&self, channel: String, payload: &str) {
        // No subscriber is not an error (PUBLISH to nobody is fine too).
        let _ = self.bus.send((channel.into(), payload.into()));
    }

    pub fn ring(&self, stage: &str) {
        self.publish(self.keys.ring(stage), stage);
    }

    pub fn publish_event(&self, channel: &str, payload: &str) {
        self.publish(self.keys.events(channel), payload);
    }

    pub fn doorbell(&self, stages: &[String]) -> Doorbell {
        let channels = stages.iter().map(|s| self.keys.ring(s)).collect();
        doorbell::doorbell(Source::Local(self.bus.subscribe()), channels)
    }

    pub fn subscribe_events(&self, channel: &str) -> EventStream {
        doorbell::event_stream(
            Source::Local(self.bus.subscribe()),
            self.keys.events(channel),
        )
    }

    pub fn try_acquire(&self, limit: &RateLimit, n: u32) -> RateDecision {
        let now_ms = self.now_ms();
        let mut state = self.state();
        state
            .buckets
            .entry(limit.name.clone())
            .or_insert_with(|| TokenBucket::full(limit.per_minute, now_ms))
            .take(limit.per_minute, n, now_ms)
    }

    pub fn take_slot(&self, pool: &str, capacity: u32, holder: &str, ttl: Duration) -> bool {
        let now = Instant::now();
        let mut state = self.state();
        let holders = state.slots.entry(pool.to_owned()).or_default();
        holders.retain(|_, expires_at| *expires_at > now);
        let room = u32::try_from(holders.len()).unwrap_or(u32::MAX) < capacity;
        let taken = if holders.contains_key(holder) || room {
            holders.insert(holder.to_owned(), now + ttl);
            true
        } else {
            false
        };
        if holders.is_empty() {
            state.slots.remove(pool);
        }
        taken
    }

    pub fn release_slot(&self, pool: &str, holder: &str) -> bool {
        let mut state = self.state();
        state
            .slots
            .get_mut(pool)
            .and_then(|holders| holders.remove(holder))
            .is_some()
    }

    pub fn set_progress(&self, job_id: i64, stage: &str, progress: &Progress) {
        let now = Instant::now();
        let mut state = self.state();
        state.progress.retain(|_, job| job.expires_at > now);
        let job = state.progress.entry(job_id).or_insert_with(|| JobProgress {
            expires_at: now,
            stages: BTreeMap::new(),
        });
        job.expires_at = now + self.options.progress_ttl;
        job.stages.insert(stage.to_owned(), progress.clone());
    }

    pub fn progress(&self, job_id: i64) -> BTreeMap<String, Progress> {
        let now = Instant::now();
        let state = self.state();
        match state.progress.get(&job_id) {
            Some(job) if job.expires_at > now => job.stages.clone(),
            _ => BTreeMap::new(),
        }
    }

    pub fn progress_ttl(&self, job_id: i64) -> Option<Duration> {
        let now = Instant::now();
        let state = self.state();
        state
            .progress
            .get(&job_id)
            .and_then(|job| job.expires_at.checked_duration_since(now))
            .filter(|left| !left.is_zero())
    }

    pub fn clear(&self) -> u64 {
        let mut state = self.state();
        let count = state.buckets.len() + state.slots.len() + state.progress.len();
        *state = State::default();
        u64::try_from(count).unwrap_or(u64::MAX)
    }
}
