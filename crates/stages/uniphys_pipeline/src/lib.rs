//! The in-process UniPhys pipeline for one asset, needing no servers: ingest, prepare (frame and
//! mass properties), ground (built-in grounder, optionally a UniPhysGen model server), colliders
//! (convex decomposition) and export.
//! The job-queue workers run the same stage functions; `uniphys run` calls [`run`].

mod colors;
mod error;
mod learned;
mod parallel;
mod progress;
mod run;

pub use error::{PipelineError, PipelineResult};
pub use learned::LearnedOptions;
pub use progress::{NoProgress, Progress, Stage};
pub use run::{RunOptions, RunOutput, asset_name, run};
