//! What one measurement returns, and the checks and statistics over it.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use anyhow::ensure;

/// How long idle workers get to start (connect, register, listen) before the first latency
/// submission.
pub(crate) const WARM_UP: Duration = Duration::from_millis(500);

/// The fallback poll of workers woken by the doorbell: the worker's default `poll_interval`.
pub(crate) const DOORBELL_POLL: Duration = Duration::from_secs(1);

/// Keys of the background jobs a latency measurement runs under start here; the probe jobs
/// measured are `0..jobs`.
pub(crate) const BACKGROUND_KEY_BASE: u64 = 1 << 40;

/// How a latency measurement submits its probe jobs and the load it runs under.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Probes {
    /// Waiting workers.
    pub workers: u32,
    /// Probe jobs, submitted one at a time.
    pub jobs: u32,
    /// Mean gap between two probes.
    pub gap: Duration,
    /// A worker that found nothing waits this long before it polls again.
    pub poll: Duration,
    /// Background jobs submitted a second meanwhile (0: an idle queue).
    pub load_per_sec: u32,
}

/// The two systems compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum System {
    /// `uniphys_queue` on PostgreSQL.
    Uniphys,
    /// apalis 1.0 with apalis-postgres 1.0.
    Apalis,
}

impl System {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Uniphys => "uniphys",
            Self::Apalis => "apalis",
        }
    }
}

/// How idle workers learn about a new job.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Wakeup {
    /// They poll, sleeping `poll_ms` after an empty claim (apalis: its `IntervalStrategy`).
    Poll,
    /// apalis only: polling every `poll_ms` with [`crate::rearming_poll::RearmingInterval`].
    PollRearmed,
    /// apalis only: PostgreSQL `LISTEN/NOTIFY` (apalis-postgres `with_pubsub`).
    Notify,
    /// UniPhys only: the service's doorbell (Redis PUBLISH, rung after submit), polling every
    /// [`DOORBELL_POLL`] as the fallback, as the worker does by default.
    Doorbell,
}

impl Wakeup {
    pub(crate) fn name(self, poll_ms: u64) -> String {
        match self {
            Self::Poll => format!("poll {poll_ms} ms"),
            Self::PollRearmed => format!("poll {poll_ms} ms, re-arming timer"),
            Self::Notify => "LISTEN/NOTIFY".to_owned(),
            Self::Doorbell => format!("Redis doorbell, poll {} ms", DOORBELL_POLL.as_millis()),
        }
    }
}

/// One throughput measurement: `jobs` pre-enqueued one-stage jobs run to completion by
/// `workers` concurrent workers.
#[derive(Debug)]
pub(crate) struct ThroughputRun {
    pub system: System,
    pub workers: u32,
    /// From starting the workers until the last completion is committed.
    pub elapsed: Duration,
    /// The job keys in the order the workers started them (one entry per execution).
    pub executed: Vec<u64>,
}

impl ThroughputRun {
    pub(crate) fn transitions_per_sec(&self) -> f64 {
        let done = u32::try_from(self.executed.len()).unwrap_or(u32::MAX);
        f64::from(done) / self.elapsed.as_secs_f64()
    }
}

/// One latency measurement: probe jobs submitted one at a time to waiting workers, on an idle
/// queue or under a background load.
#[derive(Debug)]
pub(crate) struct LatencyRun {
    pub system: System,
    pub wakeup: Wakeup,
    /// From calling submit until a worker holds the job, milliseconds, one per job.
    pub enqueue_to_start_ms: Vec<f64>,
    /// How long the submit call itself took, milliseconds, one per job.
    pub submit_ms: Vec<f64>,
    /// The probe jobs' keys in the order the workers started them (one entry per execution).
    pub executed: Vec<u64>,
    /// Background jobs submitted during the measurement (all checked to have run once).
    pub background_jobs: usize,
    /// Their rate asked for, per second.
    pub load_per_sec: u32,
    /// Workers that had not returned 15 s after being stopped (aborted; apalis only).
    pub stuck_workers: u32,
}

/// Fails unless every key in `0..jobs` was executed exactly once.
pub(crate) fn check_exactly_once(executed: &[u64], jobs: u32, what: &str) -> anyhow::Result<()> {
    let mut counts: BTreeMap<u64, u32> = BTreeMap::new();
    for key in executed {
        *counts.entry(*key).or_default() += 1;
    }
    let twice: Vec<u64> = counts
        .iter()
        .filter(|(_, n)| **n > 1)
        .map(|(k, _)| *k)
        .collect();
    let missing = (0..u64::from(jobs))
        .filter(|k| !counts.contains_key(k))
        .count();
    let unknown = counts.keys().filter(|k| **k >= u64::from(jobs)).count();
    ensure!(
        twice.is_empty() && missing == 0 && unknown == 0,
        "{what}: {} jobs ran more than once (first: {:?}), {missing} never ran, {unknown} unknown",
        twice.len(),
        twice.first(),
    );
    Ok(())
}

/// Pairs the submit instants with the start instants by job key (in `0..jobs`):
/// milliseconds from submit to start, per job.
pub(crate) fn latencies_ms(
    submitted: &[Instant],
    started: &[(u64, Instant)],
) -> anyhow::Result<Vec<f64>> {
    let mut out = Vec::with_capacity(started.len());
    for (key, at) in started {
        let index = usize::try_from(*key)?;
        let Some(sent) = submitted.get(index) else {
            anyhow::bail!("job key {key} was never submitted");
        };
        out.push(at.saturating_duration_since(*sent).as_secs_f64() * 1e3);
    }
    Ok(out)
}

/// The `q`-quantile (0..=1) of `values` by nearest rank; 0 when empty.
pub(crate) fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_is_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile(&v, 0.5), 50.0);
        assert_eq!(quantile(&v, 0.99), 99.0);
        assert_eq!(quantile(&v, 1.0), 100.0);
        assert_eq!(quantile(&[], 0.5), 0.0);
    }

    #[test]
    fn exactly_once_catches_duplicates_and_gaps() {
        assert!(check_exactly_once(&[0, 1, 2], 3, "ok").is_ok());
        assert!(check_exactly_once(&[0, 1, 1, 2], 3, "dup").is_err());
        assert!(check_exactly_once(&[0, 2], 3, "gap").is_err());
        assert!(check_exactly_once(&[0, 1, 2, 3], 3, "extra").is_err());
    }
}
