//! The stages this worker binary can run.

mod convert;
mod decompose;
mod ground;
mod infer;
mod ingest;
mod relay;
mod standin;
mod upstream;
mod verify;

pub use convert::ConvertStage;
pub use decompose::DecomposeStage;
pub use ground::GroundStage;
pub use infer::InferStage;
pub use ingest::IngestStage;
pub use standin::{StandInStage, standin_output};
pub use upstream::{FACE_PARTS_FILE, GROUNDED_FILE, INFERRED_FILE, INGESTED_FILE, VERIFIED_FILE};
pub use verify::VerifyStage;
