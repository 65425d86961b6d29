//! Geometry kernel of the UniPhys service: triangle meshes with their materials, bounds, surface
//! sampling, voxelised volume, mass properties, contact regions between parts, plane fitting,
//! k-means and convex decomposition. Synchronous, CPU only, deterministic for a given seed.
//!
//! Coordinates are `f64` metres in the object frame (Z up) once an asset has been ingested.

mod aabb;
mod error;
mod mesh;
mod mesh_asset;

pub use aabb::Aabb;
pub use error::{GeometryError, GeometryResult};
pub use glam::{DMat3, DMat4, DVec3};
pub use mesh::TriMesh;
pub use mesh_asset::{MeshAsset, MeshPart, SurfaceMaterial, Texture};
