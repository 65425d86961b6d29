//! Ingestion of 3D inputs for the UniPhys service: glTF/GLB, OBJ (+MTL), PLY, STL and URDF
//! (PartNet-Mobility folders included) become a [`uniphys_geometry::MeshAsset`] in the service
//! frame (Z up, metres) with a [`uniphys_types::SourceInfo`].
//!
//! Reading is defensive: file sizes are checked before reading, declared counts are checked
//! against the bytes present before anything is allocated, third-party parsers run under a
//! panic guard, referenced files must stay inside the asset's directory, and every error names
//! the file and says what to fix.
//!
//! Map of the crate:
//! - [`load_asset`], [`detect_format`], [`LoadedAsset`]: entry points (`load.rs`).
//! - [`IngestOptions`]: units, up axis, limits, ignored joints and a rotation (`options.rs`);
//!   [`AssetRotation`]: a seeded uniform random rotation (`rotation.rs`).
//! - [`InputFacts`], [`InputUnits`]: whether the coordinates have a unit, and the kind a
//!   PartNet-Mobility `meta.json` names (`facts.rs`).
//! - [`IngestedAsset`]: what was read, stored between the queue's stages so no later stage
//!   parses the source again (`stored.rs`).
//! - [`IngestError`], [`IngestResult`]: errors (`error.rs`).
//! - Format readers: `gltf.rs` (+ `gltf_data.rs`), `obj.rs`, `ply.rs`, `stl.rs`, `urdf.rs`
//!   (+ `urdf_tree.rs`, `urdf_joints.rs`), `primitives.rs` (URDF shapes), `texture.rs`.
//! - Plumbing: `paths.rs` (safe reference resolution), `source.rs` (limited reads, counters),
//!   `digest.rs` (content hash), `checks.rs` (part checks), `guard.rs` (panic guard).

mod checks;
mod digest;
mod error;
mod facts;
mod gltf;
mod gltf_data;
mod guard;
mod load;
mod obj;
mod options;
mod paths;
mod ply;
mod primitives;
mod rotation;
mod source;
mod stl;
mod stored;
mod texture;
mod urdf;
mod urdf_joints;
mod urdf_tree;

pub use error::{IngestError, IngestResult};
pub use facts::{InputFacts, InputUnits};
pub use load::{LoadedAsset, default_up_axis, detect_format, load_asset};
pub use options::IngestOptions;
pub use rotation::{AssetRotation, uniform_rotation};
pub use stored::{IngestedAsset, STORED_ASSET_VERSION};
