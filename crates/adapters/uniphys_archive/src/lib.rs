//! Multi-file assets in one file: a URDF folder with its meshes, an OBJ with its MTL and
//! textures, a glTF with external buffers and images, submitted as one zip or tar archive
//! (gzip allowed).
//!
//! The map:
//! - [`kind`]: which archive a file name names ([`ArchiveKind`]);
//! - [`limits`]: how much an archive may hold ([`ArchiveLimits`]);
//! - [`entry_path`]: entry names as safe relative paths (no absolute paths, no `..`);
//! - [`walk`]: every entry of a zip or tar read once, under the limits, links and special files
//!   refused;
//! - [`main_file`]: the file an asset is read from (the URDF, the glTF, the OBJ);
//! - [`unpack`]: [`inspect`] (check without writing) and [`unpack()`] (write into a folder);
//! - [`pack`]: a folder packed into a tar.gz with the same bytes every time ([`pack_folder`],
//!   over [`DeterministicTar`]).

pub mod entry_path;
mod error;
pub mod kind;
pub mod limits;
pub mod main_file;
pub mod pack;
pub mod unpack;
pub mod walk;

pub use error::{ArchiveError, ArchiveResult};
pub use kind::ArchiveKind;
pub use limits::ArchiveLimits;
pub use main_file::main_file;
pub use pack::{DeterministicTar, PackSummary, pack_folder};
pub use unpack::{Listing, inspect, unpack};
