use std::time::Duration;

/// The stages of an in-process run, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// Load and validate the input.
    Ingest,
    /// A UniPhysGen model server's answers (only when one is configured).
    Infer,
    /// Frame normalisation and per-part mass properties.
    Prepare,
    /// Convex decomposition of every part.
    Colliders,
    /// Materials, properties and articulation (built-in grounder, then the model's and an LVLM's
    /// answers).
    Ground,
    /// Intrinsic checks and articulation sweeps, with correction of failed joints.
    Verify,
    /// URDF, MJCF, meshes, record and report.
    Export,
}

impl Stage {
    /// All stages in run order.
    pub const ALL: [Stage; 7] = [
        Stage::Ingest,
        Stage::Infer,
        Stage::Prepare,
        Stage::Colliders,
        Stage::Ground,
        Stage::Verify,
        Stage::Export,
    ];

    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Stage::Ingest => "ingest",
            Stage::Infer => "infer",
            Stage::Prepare => "prepare",
            Stage::Ground => "ground",
            Stage::Colliders => "colliders",
            Stage::Verify => "verify",
            Stage::Export => "export",
        }
    }
}

/// Receives progress of a run. Implementations must be cheap; they are called from the run's thread.
pub trait Progress: Sync {
    /// A stage began.
    fn stage_started(&self, stage: Stage);
    /// `done` of `total` units of a stage are finished (e.g. parts decomposed).
    fn stage_advanced(&self, stage: Stage, done: usize, total: usize);
    /// A stage ended, with how long it took and a one-line summary.
    fn stage_finished(&self, stage: Stage, elapsed: Duration, summary: &str);
}

/// A [`Progress`] that ignores everything.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn stage_started(&self, _: Stage) {}
    fn stage_advanced(&self, _: Stage, _: usize, _: usize) {}
    fn stage_finished(&self, _: Stage, _: Duration, _: &str) {}
}
