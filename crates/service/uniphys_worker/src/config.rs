//! How a worker runs: which stages, how many at once, leases, polling, shutdown.

use std::time::Duration;

/// One stage a worker claims.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StageSlots {
    /// The stage's name.
    pub stage: String,
    /// Runs of it at once in this process.
    pub concurrency: usize,
    /// Hard limit on one run; past it the run is stopped and failed (transient).
    pub deadline: Duration,
}

impl StageSlots {
    /// `concurrency` slots of `stage`, with a one-hour deadline.
    #[must_use]
    pub fn new(stage: impl Into<String>, concurrency: usize) -> Self {
        Self {
            stage: stage.into(),
            concurrency,
            deadline: Duration::from_secs(3600),
        }
    }
}

/// Worker settings. Libraries never read the environment; binaries build this.
#[derive(Clone, Debug)]
pub struct WorkerConfig {
    /// The stages to claim.
    pub stages: Vec<StageSlots>,
    /// Lease per claim; renewed every third of it while the stage runs.
    pub lease: Duration,
    /// Longest wait between claims when no doorbell rings (the guarantee; the doorbell is a hint).
    pub poll_interval: Duration,
    /// How often this worker also recovers expired leases of dead workers.
    pub reap_interval: Duration,
    /// On shutdown, how long running stages may finish before their leases are released.
    pub shutdown_grace: Duration,
}

impl Default for WorkerConfig {
    fn default() -> Self {
        Self {
            stages: Vec::new(),
            lease: Duration::from_secs(60),
            poll_interval: Duration::from_secs(1),
            reap_interval: Duration::from_secs(15),
            shutdown_grace: Duration::from_secs(20),
        }
    }
}

impl WorkerConfig {
    /// Checks the settings; the message says what to change.
    pub fn validate(&self) -> Result<(), String> {
        if self.stages.is_empty() {
            return Err("a worker needs at least one stage to claim".into());
        }
        if let Some(s) = self.stages.iter().find(|s| s.concurrency == 0) {
            return Err(format!(
                "stage {} needs a concurrency of at least 1",
                s.stage
            ));
        }
        if self.lease < Duration::from_secs(1) {
            return Err("the lease must be at least 1 s".into());
        }
        if self.poll_interval.is_zero() {
            return Err("the poll interval must be positive".into());
        }
        Ok(())
    }
}
