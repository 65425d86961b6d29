//! The queue gauges, refilled from the store's statistics on each refresh (a stage or table
//! that disappears loses its series instead of keeping a stale value).

use std::time::Duration;

use uniphys_queue::{QueueStore, StageStats, TableHealth};

use super::Metrics;
use super::labels::{StageLabels, StageStateLabels, TableLabels};
use crate::TelemetryResult;

impl Metrics {
    /// Reads per-stage statistics (`window` bounds their throughput counts) and table health
    /// from `store` and sets the queue gauges from them. Call before encoding, or on a timer.
    pub async fn refresh_queue_gauges(
        &self,
        store: &QueueStore,
        window: Duration,
    ) -> TelemetryResult<()> {
        let stats = store.stage_stats(window).await?;
        let tables = store.table_health().await?;
        self.set_queue_gauges(&stats, &tables);
        Ok(())
    }

    /// Replaces the queue-depth, oldest-ready-age and table gauges with `stats` and `tables`.
    pub fn set_queue_gauges(&self, stats: &[StageStats], tables: &[TableHealth]) {
        let inner = &self.inner;
        // A panic elsewhere while holding the lock leaves nothing half-done worth refusing.
        let _serial = inner
            .refresh
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        inner.queue_depth.clear();
        inner.queue_oldest_ready_age.clear();
        inner.table_dead_tuples.clear();
        inner.table_live_tuples.clear();
        for stage in stats {
            let depths = [
                ("blocked", stage.blocked),
                ("ready", stage.ready),
                ("backing_off", stage.backing_off),
                ("running", stage.running),
                ("dead", stage.dead),
            ];
            for (state, n) in depths {
                let labels = StageStateLabels {
                    stage: stage.stage_name.clone(),
                    state,
                };
                inner.queue_depth.get_or_create(&labels).set(gauge_value(n));
            }
            #[expect(clippy::cast_precision_loss, reason = "ages far below 2^52 ms")]
            let age_secs = stage.oldest_ready_age_ms as f64 / 1000.0;
            inner
                .queue_oldest_ready_age
                .get_or_create(&StageLabels {
                    stage: stage.stage_name.clone(),
                })
                .set(age_secs);
        }
        for table in tables {
            let labels = TableLabels {
                table: table.table.clone(),
            };
            inner
                .table_dead_tuples
                .get_or_create(&labels)
                .set(gauge_value(table.dead_rows));
            inner
                .table_live_tuples
                .get_or_create(&labels)
                .set(gauge_value(table.live_rows));
        }
    }
}

fn gauge_value(n: u64) -> i64 {
    i64::try_from(n).unwrap_or(i64::MAX)
}
