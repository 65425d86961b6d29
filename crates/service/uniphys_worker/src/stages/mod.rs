//! The stages this worker binary can run.

mod convert;
mod decompose;
mod ground;
mod ingest;
mod relay;
mod standin;
mod upstream;

pub use convert::ConvertStage;
pub use decompose::DecomposeStage;
pub use ground::GroundStage;
pub use ingest::IngestStage;
pub use standin::{StandInStage, standin_output};
pub use upstream::{FACE_PARTS_FILE, GROUNDED_FILE};
