//! [`Hints`]: the one handle the API and workers hold, over Redis or in process.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use crate::doorbell::{Doorbell, EventStream};
use crate::error::{HintsError, HintsResult};
use crate::local::LocalHints;
use crate::progress::Progress;
use crate::rate_limit::{RateDecision, RateLimit};
use crate::redis_backend::RedisHints;

/// Timeouts and lifetimes. The defaults suit a Redis on the cluster network.
#[derive(Debug, Clone)]
pub struct HintsOptions {
    /// Bound on opening a connection (default 250 ms).
    pub connect_timeout: Duration,
    /// Bound on one command's answer (default 250 ms).
    pub response_timeout: Duration,
    /// How long a doorbell or event stream waits after a failed or lost subscription before it
    /// subscribes again (default 1 s). Also the longest pause between reconnection attempts.
    pub resubscribe_after: Duration,
    /// How long a job's progress lives after its last update (default 1 h).
    pub progress_ttl: Duration,
}

impl Default for HintsOptions {
    fn default() -> Self {
        Self {
            connect_timeout: Duration::from_millis(250),
            response_timeout: Duration::from_millis(250),
            resubscribe_after: Duration::from_secs(1),
            progress_ttl: Duration::from_secs(3600),
        }
    }
}

impl HintsOptions {
    /// The hard bound on any one call: connecting plus answering.
    pub fn op_guard(&self) -> Duration {
        self.connect_timeout + self.response_timeout
    }
}

/// Best-effort fleet hints: doorbells, rate limits, slot pools, progress, events.
///
/// Cheap to clone (an `Arc`). Every call either answers within [`HintsOptions::op_guard`] or
/// returns an error that [`HintsError::is_unavailable`] calls unavailability: the caller then
/// does without (polls, skips the update) and nothing is lost, because nothing here is the only
/// copy of any job state.
#[derive(Clone)]
pub struct Hints {
    backend: Backend,
}

#[derive(Clone)]
enum Backend {
    Redis(Arc<RedisHints>),
    Local(Arc<LocalHints>),
}

impl std::fmt::Debug for Hints {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hints")
            .field("backend", &self.backend_name())
            .finish()
    }
}

impl Hints {
    /// Hints over the Redis at `url` (`redis://host:port/db`), with every key and channel under
    /// `key_prefix`. Does not connect: a Redis that is down at start is not an error here, only
    /// in the calls made while it is down. Must be called inside a tokio runtime.
    pub fn redis(url: &str, key_prefix: &str) -> HintsResult<Self> {
        Self::redis_with_options(url, key_prefix, HintsOptions::default())
    }

    /// [`Hints::redis`] with explicit timeouts and lifetimes.
    pub fn redis_with_options(
        url: &str,
        key_prefix: &str,
        options: HintsOptions,
    ) -> HintsResult<Self> {
        Ok(Self {
            backend: Backend::Redis(Arc::new(RedisHints::new(url, key_prefix, options)?)),
        })
    }

    /// In-process hints for embedded mode: the same behaviour, shared only by this process's
    /// clones of the returned handle.
    pub fn local() -> Self {
        Self::local_with_options(HintsOptions::default())
    }

    /// [`Hints::local`] with explicit lifetimes (only `progress_ttl` applies).
    pub fn local_with_options(options: HintsOptions) -> Self {
        Self {
            backend: Backend::Local(Arc::new(LocalHints::new(options))),
        }
    }

    /// `redis` or `local`.
    pub fn backend_name(&self) -> &'static str {
        match &self.backend {
            Backend::Redis(_) => "redis",
            Backend::Local(_) => "local",
        }
    }

    /// Round trip to the hint store, for `/readyz` (the local backend answers at once).
    pub async fn ping(&self) -> HintsResult<Duration> {
        match &self.backend {
            Backend::Redis(redis) => redis.ping().await,
            Backend::Local(_) => Ok(Duration::ZERO),
        }
    }

    /// Whether the last command sent succeeded (false before the first one). Costs nothing;
    /// for metrics and `/readyz` detail.
    pub fn is_healthy(&self) -> bool {
        match &self.backend {
            Backend::Redis(redis) => redis.is_healthy(),
            Backend::Local(_) => true,
        }
    }

    /// Wakes the workers waiting on `stage`'s doorbell (call after committing new work for it).
    pub async fn ring(&self, stage: &str) -> HintsResult<()> {
        match &self.backend {
            Backend::Redis(redis) => redis.ring(stage).await,
            Backend::Local(local) => {
                local.ring(stage);
                Ok(())
            }
        }
    }

    /// A doorbell that rings for any of `stages`. It starts listening now, in a background task
    /// (so this must be called inside a tokio runtime), and stops when dropped.
    pub fn doorbell(&self, stages: &[String]) -> Doorbell {
        match &self.backend {
            Backend::Redis(redis) => redis.doorbell(stages),
            Backend::Local(local) => local.doorbell(stages),
        }
    }

    /// Takes `n` tokens from the fleet-wide `limit` if it has them.
    /// `n` must be in `1..=limit.per_minute`.
    pub async fn try_acquire(&self, limit: &RateLimit, n: u32) -> HintsResult<RateDecision> {
        limit.validate(n)?;
        match &self.backend {
            Backend::Redis(redis) => redis.try_acquire(limit, n).await,
            Backend::Local(local) => Ok(local.try_acquire(limit, n)),
        }
    }

    /// Takes one of `capacity` slots in `pool` for `holder` (a unique worker id) until `ttl`
    /// from now, unless the pool is full. True when `holder` holds a slot afterwards; taking a
    /// slot already held moves its expiry on. A holder that crashes frees its slot at expiry.
    pub async fn acquire_slot(
        &self,
        pool: &str,
        capacity: u32,
        holder: &str,
        ttl: Duration,
    ) -> HintsResult<bool> {
        self.take_slot("acquire_slot", pool, capacity, holder, ttl)
            .await
    }

    /// Moves `holder`'s slot expiry to `ttl` from now; call every `ttl / 3` while the work runs.
    /// If the slot was lost (it expired, or Redis lost its data) it is taken again when there is
    /// room. False means the pool is full without `holder`: the work may go on (it already runs),
    /// but the pool is over capacity until someone releases.
    pub async fn renew_slot(
        &self,
        pool: &str,
        capacity: u32,
        holder: &str,
        ttl: Duration,
    ) -> HintsResult<bool> {
        self.take_slot("renew_slot", pool, capacity, holder, ttl)
            .await
    }

    async fn take_slot(
        &self,
        op: &'static str,
        pool: &str,
        capacity: u32,
        holder: &str,
        ttl: Duration,
    ) -> HintsResult<bool> {
        if capacity == 0 {
            return Err(HintsError::InvalidArgument(format!(
                "slot pool {pool} has capacity 0"
            )));
        }
        if ttl.is_zero() {
            return Err(HintsError::InvalidArgument(format!(
                "slot ttl for pool {pool} is zero"
            )));
        }
        match &self.backend {
            Backend::Redis(redis) => redis.take_slot(op, pool, capacity, holder, ttl).await,
            Backend::Local(local) => Ok(local.take_slot(pool, capacity, holder, ttl)),
        }
    }

    /// Gives `holder`'s slot in `pool` back. True when it held one.
    pub async fn release_slot(&self, pool: &str, holder: &str) -> HintsResult<bool> {
        match &self.backend {
            Backend::Redis(redis) => redis.release_slot(pool, holder).await,
            Backend::Local(local) => Ok(local.release_slot(pool, holder)),
        }
    }

    /// Records `stage`'s progress on `job_id`; the job's progress expires
    /// [`HintsOptions::progress_ttl`] after its last update.
    pub async fn set_progress(
        &self,
        job_id: i64,
        stage: &str,
        progress: &Progress,
    ) -> HintsResult<()> {
        progress.validate()?;
        match &self.backend {
            Backend::Redis(redis) => {
                let json = serde_json::to_string(progress).map_err(|e| {
                    HintsError::InvalidArgument(format!("progress does not serialise: {e}"))
                })?;
                redis.set_progress(job_id, stage, json).await
            }
            Backend::Local(local) => {
                local.set_progress(job_id, stage, progress);
                Ok(())
            }
        }
    }

    /// The progress of every stage of `job_id` that reported one (empty when none, or expired).
    pub async fn progress(&self, job_id: i64) -> HintsResult<BTreeMap<String, Progress>> {
        match &self.backend {
            Backend::Redis(redis) => redis.progress(job_id).await,
            Backend::Local(local) => Ok(local.progress(job_id)),
        }
    }

    /// How long `job_id`'s progress has left to live (`None` when there is none).
    pub async fn progress_ttl(&self, job_id: i64) -> HintsResult<Option<Duration>> {
        match &self.backend {
            Backend::Redis(redis) => redis.progress_ttl(job_id).await,
            Backend::Local(local) => Ok(local.progress_ttl(job_id)),
        }
    }

    /// Publishes `payload` (usually JSON) to the subscribers of `channel`; nobody listening is
    /// not an error.
    pub async fn publish_event(&self, channel: &str, payload: &str) -> HintsResult<()> {
        match &self.backend {
            Backend::Redis(redis) => redis.publish_event(channel, payload).await,
            Backend::Local(local) => {
                local.publish_event(channel, payload);
                Ok(())
            }
        }
    }

    /// A stream of the events published on `channel` from now on (best effort). Starts a
    /// background task, so this must be called inside a tokio runtime.
    pub fn subscribe_events(&self, channel: &str) -> EventStream {
        match &self.backend {
            Backend::Redis(redis) => redis.subscribe_events(channel),
            Backend::Local(local) => local.subscribe_events(channel),
        }
    }

    /// Forgets every hint under the key prefix (rate buckets, slots, progress), as a Redis
    /// `FLUSHALL` would; returns how many keys went. For operators and tests.
    pub async fn clear(&self) -> HintsResult<u64> {
        match &self.backend {
            Backend::Redis(redis) => redis.clear().await,
            Backend::Local(local) => Ok(local.clear()),
        }
    }
}
