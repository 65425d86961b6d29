//! The in-process UniPhys pipeline for one asset, needing no servers: ingest (with `--unit
//! auto`, a real size for inputs in normalised units: `real_scale.rs`; the object put to rest on
//! the ground: `input`), infer (a UniPhysGen model server's answers, when one is configured),
//! prepare (mass properties), colliders (convex decomposition), ground (built-in grounder, then
//! the model's answers or an LVLM's when configured: `grounding`), verify
//! (intrinsic checks, articulation sweeps with correction) and export (`finish`).
//! The job-queue workers run the same stage functions: the `infer` stage calls [`infer_asset`]
//! and stores the UniPhysGen server's answers, `ground` calls [`ground_asset`] with them as
//! `RunOptions::inferred` (the server is not asked again) and stores what it returns, `verify`
//! calls [`verify_asset`] with that as `RunOptions::grounded` (no model is asked again) and
//! stores what it returns, `convert` calls [`run`] with both (`RunOptions::verified`: only export
//! runs), each on the asset `ingest` stored ([`AssetSource::Ingested`]: the source is parsed
//! once); `uniphys run` calls [`run`] on the file.

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
pub use input::{AssetSource, asset_name};
pub use learned::LearnedOptions;
pub use lvlm::LvlmOptions;
pub use progress::{NoProgress, Progress, Stage};
pub use run::{RunOptions, RunOutput, ground_asset, infer_asset, run, verify_asset};
pub use uniphys_mesh_io::IngestedAsset;
pub use uniphys_uniphysgen::ModelAnswers;
pub use verify::VerifyOptions;
