//! Artifact storage for the UniPhys service through `object_store`: a local directory by default,
//! an in-memory store for tests, an S3-compatible bucket by configuration ([`ArtifactStore::from_url`]).
//!
//! Keys are deterministic ([`ArtifactKey`]: `{asset}/{stage}/v{version}/{input_digest}/...`), so a
//! re-run of a stage on the same input writes the same keys. Stage outputs are written create-only
//! ([`ArtifactStore::put_once`], [`ArtifactStore::put_file`]): the same content under an existing key
//! is success, different content is [`StorageError::Conflict`] and the stored object stays as it was.
//!
//! - `key.rs`: [`ArtifactKey`] and key validation (no empty, `.` or `..` components).
//! - `options.rs`: [`StorageOptions`] for S3-compatible stores.
//! - `open.rs`: [`ArtifactStore::from_url`].
//! - `store.rs`: [`ArtifactStore`] and plain reads, writes, listing, streaming, deletion.
//! - `put_once.rs`: create-only writes and [`PutOutcome`].
//! - `files.rs`: streaming upload of local files and download to local files.

mod error;
mod files;
mod key;
mod open;
mod options;
mod put_once;
mod store;

pub use error::{StorageError, StorageResult};
pub use files::STAGING_PREFIX;
pub use key::ArtifactKey;
pub use options::StorageOptions;
pub use put_once::PutOutcome;
pub use store::ArtifactStore;
