//! The stages of the service's job queue, by the names their runs are claimed by: one type for
//! the worker that runs them, the API that reports them and the CLI that configures workers.

use std::fmt;

use serde::{Deserialize, Serialize};

/// A stage of the job queue's pipeline: `ingest` → `decompose` → `infer` → `ground` → `verify`
/// → `convert`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ServiceStage {
    /// Reads and checks the submitted file.
    Ingest,
    /// Splits a mesh given as one piece into parts.
    Decompose,
    /// Asks a UniPhysGen model server about the parts and the object, when one is configured (the
    /// only stage that calls it; the GPU-bound one).
    Infer,
    /// Grounds the parts: materials, properties, masses and joints, by the built-in grounder, then
    /// the UniPhysGen server's answers `infer` stored and, when configured, an LVLM (the only
    /// stage that calls it).
    Ground,
    /// Verifies the grounded asset: intrinsic checks, joints swept (and corrected when they fail
    /// their sweep), the dynamic check.
    Verify,
    /// Exports the verified asset (URDF, MJCF, meshes, record, report); in a job without a
    /// `verify` stage (submitted before it existed) it verifies first.
    Convert,
}

impl ServiceStage {
    /// Every stage, in pipeline order.
    pub const ALL: [Self; 6] = [
        Self::Ingest,
        Self::Decompose,
        Self::Infer,
        Self::Ground,
        Self::Verify,
        Self::Convert,
    ];

    /// The name runs are claimed by and stored under.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Ingest => "ingest",
            Self::Decompose => "decompose",
            Self::Infer => "infer",
            Self::Ground => "ground",
            Self::Verify => "verify",
            Self::Convert => "convert",
        }
    }

    /// The stage of a name, if it is one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

impl fmt::Display for ServiceStage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stage_is_named_as_it_serialises_and_read_back_by_its_name() {
        for stage in ServiceStage::ALL {
            assert_eq!(
                serde_json::to_value(stage).expect("a stage serialises"),
                stage.name()
            );
            assert_eq!(ServiceStage::from_name(stage.name()), Some(stage));
        }
        assert_eq!(ServiceStage::from_name("convrt"), None);
    }
}
