//! The in-process UniPhys pipeline for one asset, needing no servers: ingest (and, with
//! `--unit auto`, a real size for inputs in normalised units: `real_scale.rs`), prepare (frame and
//! mass properties), colliders (convex decomposition), ground (built-in grounder, optionally a
//! UniPhysGen model server or an LVLM), verify (intrinsic checks, articulation sweeps with correction) and
//! export.
//! The job-queue workers run the same stage functions; `uniphys run` calls [`run`].

mod cavities;
mod error;
mod learned;
mod lvlm;
mod mass_calibration;
mod preview;
mod progress;
mod real_scale;
mod run;
mod verify;

pub use error::{PipelineError, PipelineResult};
pub use learned::LearnedOptions;
pub use lvlm::LvlmOptions;
pub use progress::{NoProgress, Progress, Stage};
pub use run::{RunOptions, RunOutput, asset_name, run};
pub use verify::VerifyOptions;
