//! The dashboard's board: the latest queue statistics, recomputed at most once per refresh
//! interval however many viewers poll (one query in flight; meanwhile the others get the previous
//! statistics, or wait for the first), a history of samples taken every history interval by a
//! background task, each tenant's job counts cached for the same refresh interval, and batch
//! statistics cached for `batch_stats_refresh`.

use std::collections::VecDeque;
use std::sync::{Arc, Weak};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use uniphys_queue::{JobState, QueueResult, QueueStore, StageStats, TenantId};

use crate::routes::batches::BatchStatsResponse;
use crate::state::ApiState;
use crate::ttl_cache::TtlCache;

/// One stage at one moment of the history.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct StagePoint {
    pub stage: String,
    pub depth: u64,
    pub running: u64,
    pub failed: u64,
    pub throughput_per_sec: f64,
}

/// Every stage at one moment.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Sample {
    pub at_ms: i64,
    pub stages: Vec<StagePoint>,
}

/// The statistics as last computed.
#[derive(Debug)]
pub(crate) struct Snapshot {
    pub at_ms: i64,
    pub stages: Vec<StageStats>,
}

/// Shared by every request of one router.
#[derive(Debug)]
pub(crate) struct Board {
    /// The latest statistics (one entry).
    latest: TtlCache<(), Snapshot>,
    history: std::sync::Mutex<VecDeque<Sample>>,
    tenants: TtlCache<TenantId, Vec<(JobState, u64)>>,
    /// Batch statistics by tenant and label (`GET /v1/batches/{batch}/stats`).
    pub(crate) batches: TtlCache<(TenantId, String), BatchStatsResponse>,
}

impl Default for Board {
    fn default() -> Self {
        Self {
            latest: TtlCache::new(1),
            history: std::sync::Mutex::default(),
            tenants: TtlCache::new(10_000),
            batches: TtlCache::new(1_000),
        }
    }
}

impl Board {
    /// The statistics, recomputed when older than `refresh`; while one caller recomputes them,
    /// the others get the previous ones.
    pub(crate) async fn snapshot(
        &self,
        store: &QueueStore,
        window: Duration,
        refresh: Duration,
    ) -> QueueResult<Arc<Snapshot>> {
        self.latest
            .get_or_compute((), refresh, async {
                Ok(Snapshot {
                    stages: store.stage_stats(window).await?,
                    at_ms: now_ms(),
                })
            })
            .await
    }

    /// The tenant's jobs by state, recomputed when older than `refresh`.
    pub(crate) async fn tenant_jobs(
        &self,
        store: &QueueStore,
        tenant: TenantId,
        refresh: Duration,
    ) -> QueueResult<Arc<Vec<(JobState, u64)>>> {
        self.tenants
            .get_or_compute(tenant, refresh, async {
                Ok(store.tenant_job_states(tenant).await?.into_iter().collect())
            })
            .await
    }

    /// The samples taken after `since_ms`, oldest first.
    pub(crate) fn history_since(&self, since_ms: i64) -> Vec<Sample> {
        let history = self
            .history
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        history
            .iter()
            .filter(|s| s.at_ms > since_ms)
            .cloned()
            .collect()
    }

    fn record(&self, snapshot: &Snapshot, keep: usize) {
        let sample = Sample {
            at_ms: snapshot.at_ms,
            stages: snapshot
                .stages
                .iter()
                .map(|s| StagePoint {
                    stage: s.stage_name.clone(),
                    depth: s.ready + s.backing_off,
                    running: s.running,
                    failed: s.dead,
                    throughput_per_sec: s.throughput_per_sec(),
                })
                .collect(),
        };
        let mut history = self
            .history
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if history
            .back()
            .is_some_and(|last| last.at_ms >= sample.at_ms)
        {
            return;
        }
        history.push_back(sample);
        while history.len() > keep.max(1) {
            history.pop_front();
        }
    }
}

/// Takes a history sample every `history_interval` until the router's state is dropped.
pub(crate) async fn sample_history(state: Weak<ApiState>) {
    loop {
        let Some(state) = state.upgrade() else {
            return;
        };
        let config = &state.config;
        let interval = config.history_interval;
        match state
            .board
            .snapshot(&state.store, config.stats_window, interval / 2)
            .await
        {
            Ok(snapshot) => state.board.record(&snapshot, config.history_len),
            Err(e) => tracing::warn!(error = %e, "the dashboard history skipped a sample"),
        }
        drop(state);
        tokio::time::sleep(interval).await;
    }
}

/// The wall clock, Unix milliseconds.
pub(crate) fn now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snapshot(at_ms: i64, ready: u64) -> Snapshot {
        Snapshot {
            at_ms,
            stages: vec![StageStats {
                stage_name: "ingest".into(),
                ready,
                backing_off: 1,
                window: Duration::from_secs(10),
                succeeded_in_window: 5,
                ..StageStats::default()
            }],
        }
    }

    #[test]
    fn the_history_keeps_the_newest_samples_in_order_and_answers_after_a_time() {
        let board = Board::default();
        for (i, at_ms) in [100, 200, 200, 300, 400].into_iter().enumerate() {
            board.record(&snapshot(at_ms, i as u64), 3);
        }
        let all = board.history_since(0);
        let times: Vec<i64> = all.iter().map(|s| s.at_ms).collect();
        assert_eq!(
            times,
            [200, 300, 400],
            "a repeated time is dropped, the oldest go"
        );
        assert_eq!(all[0].stages[0].depth, 2, "depth is ready + backing off");
        assert!((all[0].stages[0].throughput_per_sec - 0.5).abs() < 1e-12);
        let later: Vec<i64> = board.history_since(300).iter().map(|s| s.at_ms).collect();
        assert_eq!(later, [400]);
    }
}
