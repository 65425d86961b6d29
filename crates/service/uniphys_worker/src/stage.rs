//! What a stage is to a worker: a named, versioned, synchronous function from an asset and its
//! upstream manifests to written artifacts and a summary.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use serde_json::Value;
use tokio::sync::watch;
use uniphys_queue::{AssetInfo, OutputManifest};
use uniphys_storage::ArtifactStore;

use crate::outputs::OutputWriter;

/// A stage the worker can run. `run` is called on a blocking thread, never on the async runtime.
pub trait Stage: Send + Sync + 'static {
    /// The name runs are claimed by (`ingest`, `convert`, …).
    fn name(&self) -> &str;
    /// Bump when the stage's outputs change for the same inputs (it is part of the output keys).
    fn version(&self) -> u32;
    /// Runs the stage: reads its input, writes its artifacts through `out`, returns a summary.
    /// Check `control.cancelled()` between steps of long work.
    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError>;
}

/// Why a stage did not finish.
#[derive(Debug, thiserror::Error)]
pub enum StageError {
    /// Worth retrying (a server was unavailable, a timeout).
    #[error("{0}")]
    Transient(String),
    /// Retrying cannot help (the input is broken); the run is dead-lettered at once.
    #[error("{0}")]
    Permanent(String),
    /// The run was cancelled or its lease lost while it ran.
    #[error("stopped: the run was cancelled or its lease was lost")]
    Stopped,
}

/// What a stage reads.
#[derive(Clone)]
pub struct StageInput {
    /// The asset (its content is at `asset.source_uri` in `artifacts`).
    pub asset: AssetInfo,
    /// The job's id.
    pub job_id: i64,
    /// Manifests of the stages this one depends on, by stage name.
    pub upstream: Vec<(String, OutputManifest)>,
    /// The artifact store.
    pub artifacts: ArtifactStore,
    /// The runtime, for blocking on store calls from the stage's thread.
    pub runtime: tokio::runtime::Handle,
}

impl StageInput {
    /// Reads the object at `key` (blocking).
    pub fn fetch(&self, key: &str) -> Result<Vec<u8>, StageError> {
        self.runtime
            .block_on(self.artifacts.get(key))
            .map_err(|e| StageError::Transient(format!("reading {key}: {e}")))
    }

    /// The manifest of upstream stage `stage`.
    pub fn upstream(&self, stage: &str) -> Result<&OutputManifest, StageError> {
        self.upstream
            .iter()
            .find(|(name, _)| name == stage)
            .map(|(_, m)| m)
            .ok_or_else(|| StageError::Permanent(format!("no output of upstream stage {stage}")))
    }
}

/// Progress a stage reports: a fraction in [0, 1] and a short message.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StageProgress {
    /// Done fraction.
    pub fraction: f64,
    /// What it is doing.
    pub message: String,
}

/// Cancellation and progress for a running stage.
#[derive(Clone, Debug)]
pub struct StageControl {
    stopped: Arc<AtomicBool>,
    progress: watch::Sender<StageProgress>,
}

impl StageControl {
    /// A control and the receiving end of its progress.
    #[must_use]
    pub fn new() -> (Self, watch::Receiver<StageProgress>) {
        let (tx, rx) = watch::channel(StageProgress::default());
        (
            Self {
                stopped: Arc::new(AtomicBool::new(false)),
                progress: tx,
            },
            rx,
        )
    }

    /// Whether the run should stop (cancelled, lease lost, deadline passed or shutdown).
    #[must_use]
    pub fn cancelled(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }

    /// `Err(Stopped)` once the run should stop: `control.check()?` between steps.
    pub fn check(&self) -> Result<(), StageError> {
        if self.cancelled() {
            Err(StageError::Stopped)
        } else {
            Ok(())
        }
    }

    /// Asks the stage to stop.
    pub fn stop(&self) {
        self.stopped.store(true, Ordering::Relaxed);
    }

    /// Reports progress (cheap; the latest value wins).
    pub fn progress(&self, fraction: f64, message: impl Into<String>) {
        let fraction = fraction.clamp(0.0, 1.0);
        self.progress.send_replace(StageProgress {
            fraction,
            message: message.into(),
        });
    }
}
