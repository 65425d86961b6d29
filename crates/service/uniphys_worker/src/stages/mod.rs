//! The stages this worker binary can run.

mod convert;
pub(crate) mod decompose;
mod ingest;
mod standin;

pub use convert::ConvertStage;
pub use decompose::{DecomposeStage, FACE_PARTS_FILE};
pub use ingest::IngestStage;
pub use standin::{StandInStage, standin_output};
