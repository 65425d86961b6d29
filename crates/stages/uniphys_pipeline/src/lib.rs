//! The in-process UniPhys pipeline for one asset, needing no servers: ingest (with `--unit
//! auto`, a real size for inputs in normalised units: `real_scale.rs`; the object put to rest on
//! the ground: `input`), prepare (mass properties), colliders (convex decomposition), ground
//! (built-in grounder, optionally a UniPhysGen model server or an LVLM: `grounding`), verify
//! (intrinsic checks, articulation sweeps with correction) and export (`finish`).
//! The job-queue workers run the same stage functions: the `ground` stage calls [`ground_asset`]
//! and stores what it returns, `verify` calls [`verify_asset`] with it as `RunOptions::grounded`
//! (no model is asked again) and stores what that returns, `convert` calls [`run`] with both
//! (`RunOptions::verified`: only export runs); `uniphys run` calls [`run`].

mod cavities;
mod error;
mod finish;
mod grounding;
mod input;
mod learned;
mod lvlm;
mod mass_calibration;
mod preview;
mod progress;
mod real_scale;
mod run;
mod verify;

pub use error::{PipelineError, PipelineResult};
pub use input::asset_name;
pub use learned::LearnedOptions;
pub use lvlm::LvlmOptions;
pub use progress::{NoProgress, Progress, Stage};
pub use run::{RunOptions, RunOutput, ground_asset, run, verify_asset};
pub use verify::VerifyOptions;
