//! Geometry kernel of the UniPhys service: triangle meshes with their materials, bounds, surface
//! sampling, voxelised volume, mass properties of solids and of thin walls, contact regions and
//! distances between parts, ray casts against a mesh, plane fitting, convex outlines in a plane, k-means, optimal
//! one-to-one assignment, convex decomposition, a parallel map over independent work, and the
//! sRGB and texel helpers the renderers share. Synchronous, CPU only, deterministic for
//! a given seed.
//!
//! Coordinates are `f64` metres in the object frame (Z up) once an asset has been ingested.

mod aabb;
mod assignment;
mod bitset;
mod carve;
mod color;
mod components;
mod contact;
mod convex;
mod display_color;
mod eigen;
mod error;
mod exposure;
mod hull;
mod inertia;
mod kdtree;
mod kmeans;
mod mass;
mod mesh;
mod mesh_asset;
mod orientation;
mod outline;
mod parallel;
mod plane;
mod ray_mesh;
mod rng;
mod sampling;
mod shell;
mod solid;
#[cfg(test)]
mod test_shapes;
mod tri_box;
mod vhacd;
mod voxel;
mod voxel_raster;

pub use aabb::Aabb;
pub use assignment::{assignment_cost, min_cost_assignment};
pub use carve::{OrientedBox, carve_out};
pub use color::{linear_to_srgb8, srgb8_to_linear, texel_rgba8};
pub use components::connected_components;
pub use contact::{ContactParams, ContactRegion, DistanceProbe, contact_region, min_distance_m};
pub use convex::{ConvexParams, convex_decomposition, convex_decompositions};
pub use display_color::{display_rgba, materials_by_coverage};
pub use eigen::symmetric_eigen;
pub use error::{GeometryError, GeometryResult};
pub use exposure::{ExposureProbe, sphere_directions};
pub use glam::{DMat3, DMat4, DQuat, DVec3};
pub use hull::convex_hull;
pub use inertia::{TRIANGLE_MARGIN, inertia_is_physical, with_triangle_margin};
pub use kdtree::KdTree;
pub use kmeans::{KMeans, kmeans};
pub use mass::MassProperties;
pub use mesh::TriMesh;
pub use mesh_asset::{MeshAsset, MeshPart, SurfaceMaterial, Texture};
pub use orientation::{box_axes, extent_along, principal_axes, projection_range};
pub use outline::{convex_outline, outline_area};
pub use parallel::parallel_map;
pub use plane::{Plane, fit_plane, fit_plane_ransac};
pub use ray_mesh::RayMesh;
pub use rng::SplitMix64;
pub use sampling::{SurfaceSamples, sample_points, sample_surface};
pub use shell::WallSamples;
pub use solid::{VolumeMethod, solid_mass_properties};
pub use voxel::{MAX_VOXEL_RESOLUTION, VoxelGrid, voxelize};
