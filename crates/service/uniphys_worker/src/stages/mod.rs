//! The stages this worker binary can run.

mod convert;
mod ingest;
mod standin;

pub use convert::ConvertStage;
pub use ingest::IngestStage;
pub use standin::{StandInStage, standin_output};
