//! Artifact storage for the UniPhys service through `object_store`: a local directory by default
//! (S3-compatible stores plug in the same way). Keys are deterministic, so re-running a stage on the
//! same input writes the same keys; writes are whole-object puts and therefore idempotent.

mod error;
mod key;
mod store;

pub use error::{StorageError, StorageResult};
pub use key::ArtifactKey;
pub use store::ArtifactStore;
