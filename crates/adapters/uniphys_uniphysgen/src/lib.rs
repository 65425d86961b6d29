//! UniPhysGen inference stage (reference section 14): point clouds of an asset and its parts,
//! the model frame ("AABB-normalised, shifted to [0, 2]") and its voxel grid, the model-server
//! contract (`proto/uniphysgen/v1`) and a blocking client for it, restoration of the answers to
//! the object frame and SI units, and the reference's npz layout.
//!
//! Flow: [`prepare_points`] → [`model_inputs`] → [`UniPhysGenClient`] ([`ModelAnswers`]: what
//! it answered, kept) → `restore_*`.
//! Everything before the client is CPU-only and deterministic for a given seed.

mod answers;
mod client;
pub mod contract;
mod crc32;
mod error;
mod frame;
mod grid;
mod npy;
mod npz;
mod points;
pub mod restore;
mod slots;
pub mod test_server;
mod zip;

pub use answers::{MODEL_ANSWERS_VERSION, ModelAnswers};
pub use client::{ClientConfig, PartAnswers, UniPhysGenClient};
pub use contract::{PredictRequest, PredictResponse, Task};
pub use error::{UniPhysGenError, UniPhysGenResult};
pub use frame::{CoordinateFrame, CoordinateFrameJson, SCALE_EPSILON};
pub use grid::{DEFAULT_NUM_BINS, FeatureRow, MAX_NUM_BINS, ModelInputs, VoxelGrid, model_inputs};
pub use npz::write_npzs;
pub use points::{PointCloud, PointOptions, PreparedAsset, part_point_count, prepare_points};
pub use restore::{RestoredMotion, RestoredObject, axis_from_spherical_deg};
pub use slots::{LocalSlots, SlotLimiter};
