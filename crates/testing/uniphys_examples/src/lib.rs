//! Procedural example assets with ground truth, and a deterministic GLB writer.
//!
//! The examples (a cabinet with a drawer and a door, a laptop, a box with a hinged lid and a mug)
//! are built from closed boxes and solids of revolution in the service frame (Z up, metres, resting
//! on z = 0, centred on x/y). Each comes with the joints a correct pipeline should find
//! ([`ExpectedJoint`]) and the same joints as [`uniphys_types::Joint`] values in
//! [`uniphys_geometry::MeshAsset::joints`]. The GLB files under `test_data/examples/` are written
//! by [`write_catalogue`].
//!
//! Map of the crate:
//! - [`glb_writer`]: [`write_glb`] and [`GlbFrame`], a general `MeshAsset` to glTF 2.0 binary
//!   writer (the container packing lives in `glb_container`).
//! - [`shapes`]: closed solids with outward winding (boxes, open boxes, solids of revolution,
//!   cylinders, tubes, torus segments) and rigid transforms.
//! - `materials`: the named visual materials used by the examples.
//! - `assembly`: builds an [`ExampleAsset`] from parts and expected joints.
//! - [`ExampleAsset`] and [`ExpectedJoint`]: the ground-truth types (`example_asset`).
//! - `cabinet`, `laptop`, `box_with_lid`, `mug`: one example each.
//! - [`catalogue()`], [`example`], [`write_catalogue`]: the list of examples (`catalogue`).
//! - [`shared_partnet_object`]: the folder of a real object of the shared PartNet-Mobility set
//!   beside the repository, for tests on real data (`shared_objects`).

mod assembly;
mod box_with_lid;
mod cabinet;
mod catalogue;
mod error;
mod example_asset;
mod glb_container;
pub mod glb_writer;
mod laptop;
mod materials;
mod mug;
pub mod shapes;
mod shared_objects;

pub use catalogue::{EXAMPLE_NAMES, catalogue, example, write_catalogue};
pub use error::ExamplesError;
pub use example_asset::{ExampleAsset, ExpectedJoint};
pub use glb_writer::{GlbFrame, write_glb};
pub use shared_objects::shared_partnet_object;
