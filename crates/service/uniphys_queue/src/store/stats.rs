//! Per-stage queue statistics for dashboards, metrics and backpressure.

use std::collections::BTreeMap;
use std::time::Duration;

use super::QueueStore;
use super::claim::millis;
use crate::QueueResult;
use crate::db::{Sql, args};

/// The state of one stage's queue.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageStats {
    /// The stage.
    pub stage_name: String,
    /// Whether claims of it are paused.
    pub paused: bool,
    /// Runs waiting for upstream stages.
    pub blocked: u64,
    /// Runs claimable now: the queue depth.
    pub ready: u64,
    /// Runs waiting for a retry backoff to end.
    pub backing_off: u64,
    /// Runs leased by a worker.
    pub running: u64,
    /// Dead-lettered runs (until retried or purged).
    pub dead: u64,
    /// Runs that succeeded within the window.
    pub succeeded_in_window: u64,
    /// Failed attempts (including expired leases) within the window.
    pub failed_in_window: u64,
    /// How long the oldest claimable run has been claimable, milliseconds; 0 when none.
    pub oldest_ready_age_ms: u64,
    /// The window the `_in_window` counts cover.
    pub window: Duration,
}

impl StageStats {
    /// Succeeded runs per second over the window.
    #[must_use]
    pub fn throughput_per_sec(&self) -> f64 {
        let secs = self.window.as_secs_f64();
        if secs > 0.0 {
            #[expect(clippy::cast_precision_loss, reason = "counts far below 2^52")]
            let n = self.succeeded_in_window as f64;
            n / secs
        } else {
            0.0
        }
    }

    /// Whether no worker serves the stage: work has been claimable for the whole window, yet no
    /// run of it is leased and none finished in the window, and claims are not paused. A
    /// worker takes only the stages it is given (`UNIPHYS_STAGES`), so a deployment without a
    /// slot for one stage leaves its jobs waiting there without any error; this says so.
    #[must_use]
    pub fn unserved(&self) -> bool {
        !self.paused
            && self.ready > 0
            && self.running == 0
            && self.succeeded_in_window == 0
            && self.failed_in_window == 0
            && u128::from(self.oldest_ready_age_ms) >= self.window.as_millis()
    }
}

static STATES: Sql = Sql::new(
    "SELECT stage_name, state,
            CAST(CASE WHEN state = 'ready' AND run_after_ms > {now} THEN 1 ELSE 0 END AS BIGINT) AS later,
            CAST(count(*) AS BIGINT) AS n, min(run_after_ms) AS oldest, {now} AS now_ms
     FROM stage_runs
     WHERE state IN ('blocked', 'ready', 'running', 'dead')
     GROUP BY stage_name, state, later",
);

static SUCCEEDED: Sql = Sql::new(
    "SELECT stage_name, CAST(count(*) AS BIGINT) AS n FROM stage_runs
     WHERE finished_at_ms >= {now} - $1 AND state = 'succeeded'
     GROUP BY stage_name",
);

static FAILED: Sql = Sql::new(
    "SELECT stage_name, CAST(count(*) AS BIGINT) AS n FROM events
     WHERE at_ms >= {now} - $1 AND kind IN ('stage_failed', 'stage_dead')
     GROUP BY stage_name",
);

static PAUSED: Sql = Sql::new("SELECT stage_name FROM paused_stages");

impl QueueStore {
    /// Returns statistics for every stage that has unfinished or dead runs, recent activity, or is
    /// paused, sorted by stage name. `window` bounds the throughput and failure counts.
    pub async fn stage_stats(&self, window: Duration) -> QueueResult<Vec<StageStats>> {
        let mut session = self.db.read().await?;
        let mut by_stage: BTreeMap<String, StageStats> = BTreeMap::new();
        for row in session.fetch_all(&STATES, args![]).await? {
            let stats = entry(&mut by_stage, row.text("stage_name")?, window);
            let n = row.u64("n")?;
            match (row.text("state")?.as_str(), row.i64("later")? != 0) {
                ("blocked", _) => stats.blocked += n,
                ("ready", true) => stats.backing_off += n,
                ("ready", false) => {
                    stats.ready += n;
                    if let Some(oldest) = row.opt_i64("oldest")? {
                        let age = row.i64("now_ms")?.saturating_sub(oldest);
                        stats.oldest_ready_age_ms = u64::try_from(age).unwrap_or(0);
                    }
                }
                ("running", _) => stats.running += n,
                _ => stats.dead += n,
            }
        }
        for row in session.fetch_all(&SUCCEEDED, args![millis(window)]).await? {
            entry(&mut by_stage, row.text("stage_name")?, window).succeeded_in_window =
                row.u64("n")?;
        }
        for row in session.fetch_all(&FAILED, args![millis(window)]).await? {
            if let Some(name) = row.opt_text("stage_name")? {
                entry(&mut by_stage, name, window).failed_in_window = row.u64("n")?;
            }
        }
        for row in session.fetch_all(&PAUSED, args![]).await? {
            entry(&mut by_stage, row.text("stage_name")?, window).paused = true;
        }
        Ok(by_stage.into_values().collect())
    }
}

fn entry(
    by_stage: &mut BTreeMap<String, StageStats>,
    name: String,
    window: Duration,
) -> &mut StageStats {
    by_stage.entry(name).or_insert_with_key(|name| StageStats {
        stage_name: name.clone(),
        window,
        ..StageStats::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Work claimable for the whole minute-long window, nothing leased or finished.
    fn waiting() -> StageStats {
        StageStats {
            stage_name: "infer".into(),
            ready: 3,
            oldest_ready_age_ms: 60_000,
            window: Duration::from_secs(60),
            ..StageStats::default()
        }
    }

    #[test]
    fn a_stage_whose_work_waits_the_whole_window_untouched_is_unserved() {
        assert!(waiting().unserved());
    }

    #[test]
    fn a_stage_that_is_worked_on_paused_or_only_just_waiting_is_served() {
        let cases = [
            (
                "a run is leased",
                StageStats {
                    running: 1,
                    ..waiting()
                },
            ),
            (
                "a run succeeded",
                StageStats {
                    succeeded_in_window: 1,
                    ..waiting()
                },
            ),
            (
                "an attempt failed",
                StageStats {
                    failed_in_window: 1,
                    ..waiting()
                },
            ),
            (
                "claims are paused",
                StageStats {
                    paused: true,
                    ..waiting()
                },
            ),
            (
                "nothing is claimable",
                StageStats {
                    ready: 0,
                    ..waiting()
                },
            ),
            (
                "the work is newer than the window",
                StageStats {
                    oldest_ready_age_ms: 59_999,
                    ..waiting()
                },
            ),
        ];
        for (why, stats) in cases {
            assert!(!stats.unserved(), "{why}");
        }
    }
}
