//! The Redis implementation: one multiplexed connection (a [`ConnectionManager`], reconnecting in
//! the background) for commands, one pub/sub connection per doorbell or event stream.
//!
//! Every command runs under a hard timeout on top of the client's own connection and response
//! timeouts, so no call waits on a dead server longer than [`crate::HintsOptions::op_guard`].

use std::collections::BTreeMap;
use std::future::Future;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use redis::aio::{ConnectionManager, ConnectionManagerConfig};

use crate::doorbell::{self, Doorbell, EventStream, Source};
use crate::error::{HintsError, HintsResult};
use crate::hints::HintsOptions;
use crate::keys::Keys;
use crate::progress::Progress;
use crate::rate_limit::{RateDecision, RateLimit, WINDOW_MS};
use crate::scripts;

/// Redis-backed hints.
pub(crate) struct RedisHints {
    client: redis::Client,
    connection: ConnectionManager,
    keys: Keys,
    options: HintsOptions,
    healthy: AtomicBool,
    token_bucket: redis::Script,
    take_slot: redis::Script,
}

impl RedisHints {
    /// Parses the URL and prepares a lazy connection: nothing is sent until the first call.
    /// Must be called inside a tokio runtime.
    pub fn new(url: &str, key_prefix: &str, options: HintsOptions) -> HintsResult<Self> {
        let client =
            redis::Client::open(url).map_err(|source| HintsError::InvalidUrl { source })?;
        let config = ConnectionManagerConfig::new()
            .set_connection_timeout(Some(options.connect_timeout))
            .set_response_timeout(Some(options.response_timeout))
            // Fail the call at once and reconnect in the background: the caller polls anyway.
            .set_number_of_retries(1)
            .set_min_delay(Duration::from_millis(50))
            .set_max_delay(options.resubscribe_after);
        let connection =
            ConnectionManager::new_lazy_with_config(client.clone(), config).map_err(|source| {
                HintsError::Redis {
                    op: "connect",
                    source,
                }
            })?;
        Ok(Self {
            client,
            connection,
            keys: Keys::new(key_prefix),
            options,
            healthy: AtomicBool::new(false),
            token_bucket: redis::Script::new(scripts::TOKEN_BUCKET),
            take_slot: redis::Script::new(scripts::TAKE_SLOT),
        })
    }

    /// Runs one command (or script, or pipeline) under the hard timeout and records health.
    async fn run<T, F>(&self, op: &'static str, call: F) -> HintsResult<T>
    where
        F: Future<Output = redis::RedisResult<T>>,
    {
        let guard = self.options.op_guard();
        let outcome = match tokio::time::timeout(guard, call).await {
            Ok(Ok(value)) => Ok(value),
            Ok(Err(source)) => Err(HintsError::Redis { op, source }),
            Err(_) => Err(HintsError::Timeout {
                op,
                timeout_ms: u64::try_from(guard.as_millis()).unwrap_or(u64::MAX),
            }),
        };
        self.healthy.store(
            !matches!(&outcome, Err(e) if e.is_unavailable()),
            Ordering::Relaxed,
        );
        outcome
    }

    fn conn(&self) -> ConnectionManager {
        self.connection.clone()
    }

    pub fn is_healthy(&self) -> bool {
        self.healthy.load(Ordering::Relaxed)
    }

    pub async fn ping(&self) -> HintsResult<Duration> {
        let started = Instant::now();
        let mut conn = self.conn();
        let pong: String = self
            .run("ping", redis::cmd("PING").query_async(&mut conn))
            .await?;
        if pong != "PONG" {
            return Err(HintsError::UnexpectedReply {
                op: "ping",
                detail: pong,
            });
        }
        Ok(started.elapsed())
    }

    pub async fn publish(
        &self,
        op: &'static str,
        channel: String,
        payload: &str,
    ) -> HintsResult<()> {
        let mut conn = self.conn();
        let _receivers: i64 = self
            .run(
                op,
                redis::cmd("PUBLISH")
                    .arg(channel)
                    .arg(payload)
                    .query_async(&mut conn),
            )
            .await?;
        Ok(())
    }

    pub async fn ring(&self, stage: &str) -> HintsResult<()> {
        self.publish("ring", self.keys.ring(stage), stage).await
    }

    pub async fn publish_event(&self, channel: &str, payload: &str) -> HintsResult<()> {
        self.publish("publish_event", self.keys.events(channel), payload)
            .await
    }

    fn source(&self) -> Source {
        Source::Redis {
            client: self.client.clone(),
            connect_timeout: self.options.op_guard(),
            resubscribe_after: self.options.resubscribe_after,
        }
    }

    pub fn doorbell(&self, stages: &[String]) -> Doorbell {
        let channels = stages.iter().map(|s| self.keys.ring(s)).collect();
        doorbell::doorbell(self.source(), channels)
    }

    pub fn subscribe_events(&self, channel: &str) -> EventStream {
        doorbell::event_stream(self.source(), self.keys.events(channel))
    }

    pub async fn try_acquire(&self, limit: &RateLimit, n: u32) -> HintsResult<RateDecision> {
        let mut conn = self.conn();
        let mut invocation = self.token_bucket.key(self.keys.rate(&limit.name));
        invocation.arg(limit.per_minute).arg(n).arg(WINDOW_MS);
        let wait_ms: i64 = self
            .run("try_acquire", invocation.invoke_async(&mut conn))
            .await?;
        Ok(match u64::try_from(wait_ms) {
            Ok(0) => RateDecision::Allowed,
            Ok(ms) => RateDecision::RetryAfter(Duration::from_millis(ms)),
            Err(_) => {
                return Err(HintsError::UnexpectedReply {
                    op: "try_acquire",
                    detail: format!("negative wait {wait_ms}"),
                });
            }
        })
    }

    pub async fn take_slot(
        &self,
        op: &'static str,
        pool: &str,
        capacity: u32,
        holder: &str,
        ttl: Duration,
    ) -> HintsResult<bool> {
        let ttl_ms = u64::try_from(ttl.as_millis()).unwrap_or(u64::MAX).max(1);
        let mut conn = self.conn();
        let mut invocation = self.take_slot.key(self.keys.slots(pool));
        invocation.arg(capacity).arg(holder).arg(ttl_ms);
        let held: i64 = self.run(op, invocation.invoke_async(&mut conn)).await?;
        Ok(held == 1)
    }

    pub async fn release_slot(&self, pool: &str, holder: &str) -> HintsResult<bool> {
        let mut conn = self.conn();
        let removed: i64 = self
            .run(
                "release_slot",
                redis::cmd("ZREM")
                    .arg(self.keys.slots(pool))
                    .arg(holder)
                    .query_async(&mut conn),
            )
            .await?;
        Ok(removed > 0)
    }

    pub async fn set_progress(&self, job_id: i64, stage: &str, json: String) -> HintsResult<()> {
        let key = self.keys.progress(job_id);
        let ttl_secs = self.options.progress_ttl.as_secs().max(1);
        let mut conn = self.conn();
        let mut pipe = redis::pipe();
        pipe.atomic()
            .cmd("HSET")
            .arg(&key)
            .arg(stage)
            .arg(json)
            .ignore()
            .cmd("EXPIRE")
            .arg(&key)
            .arg(ttl_secs)
            .ignore();
        self.run("set_progress", pipe.query_async::<()>(&mut conn))
            .await
    }

    pub async fn progress(&self, job_id: i64) -> HintsResult<BTreeMap<String, Progress>> {
        let mut conn = self.conn();
        let raw: BTreeMap<String, String> = self
            .run(
                "progress",
                redis::cmd("HGETALL")
                    .arg(self.keys.progress(job_id))
                    .query_async(&mut conn),
            )
            .await?;
        raw.into_iter()
            .map(|(stage, json)| {
                serde_json::from_str(&json)
                    .map(|progress| (stage, progress))
                    .map_err(|e| HintsError::UnexpectedReply {
                        op: "progress",
                        detail: e.to_string(),
                    })
            })
            .collect()
    }

    /// Seconds left before a job's progress expires (`None`: no progress stored).
    pub async fn progress_ttl(&self, job_id: i64) -> HintsResult<Option<Duration>> {
        let mut conn = self.conn();
        let ttl_ms: i64 = self
            .run(
                "progress_ttl",
                redis::cmd("PTTL")
                    .arg(self.keys.progress(job_id))
                    .query_async(&mut conn),
            )
            .await?;
        Ok(u64::try_from(ttl_ms).ok().map(Duration::from_millis))
    }

    /// Deletes every key under the prefix; returns how many.
    pub async fn clear(&self) -> HintsResult<u64> {
        let pattern = self.keys.all_pattern();
        let mut conn = self.conn();
        let mut cursor: u64 = 0;
        let mut deleted: u64 = 0;
        loop {
            let (next, keys): (u64, Vec<String>) = self
                .run(
                    "clear",
                    redis::cmd("SCAN")
                        .arg(cursor)
                        .arg("MATCH")
                        .arg(&pattern)
                        .arg("COUNT")
                        .arg(500)
                        .query_async(&mut conn),
                )
                .await?;
            if !keys.is_empty() {
                let n: u64 = self
                    .run("clear", redis::cmd("DEL").arg(&keys).query_async(&mut conn))
                    .await?;
                deleted += n;
            }
            if next == 0 {
                return Ok(deleted);
            }
            cursor = next;
        }
    }
}
