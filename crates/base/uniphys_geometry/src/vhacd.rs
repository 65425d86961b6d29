//! V-HACD on one connected component, in the component's own frame, and the reuse of its answer
//! for moved copies of the component. Real objects repeat pieces (a keyboard's keys, an oven's
//! knobs, a cart's wheels); V-HACD takes about the same time for each whatever its size, so each
//! shape is decomposed once and its hulls are moved onto the copies.

use std::collections::HashMap;

use glam::{DMat3, DVec3, Vec3};
use parry3d::transformation::vhacd::{VHACD, VHACDParameters};
use parry3d::transformation::voxelization::VoxelSet;

use crate::convex::{ConvexParams, Hull};
use crate::{TriMesh, box_axes, convex_hull, projection_range, sample_points};

/// Two components are copies when their triangles are the same and every vertex, in each one's
/// own frame, is within this fraction of the component's largest extent of the other's. The
/// knobs of one real oven agree to about 5e-5 of their size (their tight boxes are found by a
/// search to about 1e-4 rad, and their vertices were stored in single precision); V-HACD's
/// voxels are 1/64 of it, so a hull moved from a copy is off by a hundredth of a voxel at most.
const COPY_TOLERANCE_FRACTION: f64 = 1e-4;

/// A component in the frame V-HACD decomposes it in: relative to its centroid, along the edges
/// of its tight box ([`box_axes`]), so that V-HACD's axis-aligned voxels follow the part's own
/// edges whatever its pose (a turned cabinet decomposes into the same panels as an upright one).
pub(crate) struct ComponentFrame {
    centroid: DVec3,
    /// Rows are the box axes.
    box_from_object: DMat3,
    /// The vertices in this frame, as V-HACD reads them.
    points: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// Largest extent of the points in this frame.
    extent: f64,
}

impl ComponentFrame {
    pub(crate) fn of(component: &TriMesh) -> Self {
        let centroid =
            component.positions.iter().sum::<DVec3>() / component.positions.len().max(1) as f64;
        let [a, b, c] = tight_box_axes(component);
        let box_from_object = DMat3::from_cols(a, b, c).transpose();
        let points: Vec<Vec3> = component
            .positions
            .iter()
            .map(|p| (box_from_object * (*p - centroid)).as_vec3())
            .collect();
        let (lo, hi) = points.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        Self {
            centroid,
            box_from_object,
            extent: f64::from((hi - lo).max_element()),
            points,
            triangles: component.triangles.clone(),
        }
    }

    /// Largest extent of the component, metres.
    pub(crate) fn extent(&self) -> f64 {
        self.extent
    }

    /// A point of this frame in the object frame.
    fn object_point(&self, v: DVec3) -> DVec3 {
        self.centroid + self.box_from_object.transpose() * v
    }

    /// A point of the object frame in this frame.
    fn frame_point(&self, p: DVec3) -> DVec3 {
        self.box_from_object * (p - self.centroid)
    }

    /// Whether `other` is this component moved: the same triangles over vertices that agree in
    /// their own frames.
    fn same_shape(&self, other: &Self) -> bool {
        let tolerance = COPY_TOLERANCE_FRACTION * self.extent.max(other.extent);
        self.triangles == other.triangles
            && self.points.len() == other.points.len()
            && self
                .points
                .iter()
                .zip(&other.points)
                .all(|(a, b)| f64::from((*a - *b).abs().max_element()) <= tolerance)
    }

    /// V-HACD's parts of the component as closed hulls in the object frame: the hull of the mesh
    /// clipped to each part's surface voxels, or of those voxels' corners if that fails. `None`
    /// if V-HACD panicked (a third-party failure must not take the service down).
    pub(crate) fn decompose(&self, params: &ConvexParams) -> Option<Vec<Hull>> {
        let vhacd_params = VHACDParameters {
            resolution: params.voxel_resolution,
            concavity: params.concavity_tolerance as f32,
            max_convex_hulls: u32::try_from(params.max_hulls).unwrap_or(u32::MAX),
            ..VHACDParameters::default()
        };
        let to_object = |vertices: &[Vec3]| -> Vec<DVec3> {
            vertices
                .iter()
                .map(|v| self.object_point(v.as_dvec3()))
                .collect()
        };
        let run = || {
            let decomposition =
                VHACD::decompose(&vhacd_params, &self.points, &self.triangles, true);
            decomposition
                .voxel_parts()
                .iter()
                .filter_map(|part| {
                    let clipped =
                        part.compute_primitive_intersections(&self.points, &self.triangles);
                    convex_hull(&to_object(&clipped))
                        .or_else(|_| convex_hull(&to_object(&surface_voxel_corners(part))))
                        .ok()
                        .map(Hull::new)
                })
                .collect()
        };
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)).ok()
    }

    /// The hulls `original` found for the component framed by `from`, moved onto this copy of
    /// it (each hull's corners through `from`'s frame into this one's, then their hull).
    pub(crate) fn moved_hulls(&self, from: &Self, original: &[Hull]) -> Vec<Hull> {
        original
            .iter()
            .filter_map(|hull| {
                let corners: Vec<DVec3> = hull
                    .mesh
                    .positions
                    .iter()
                    .map(|p| self.object_point(from.frame_point(*p)))
                    .collect();
                convex_hull(&corners).ok().map(Hull::new)
            })
            .collect()
    }
}

/// The edges of `mesh`'s tight box, found on surface samples (the same for any pose of it).
fn tight_box_axes(mesh: &TriMesh) -> [DVec3; 3] {
    box_axes(&sample_points(mesh, 2000, 0xb0c5))
}

/// Largest extent of `mesh` along the edges of its tight box, metres: its size whatever its
/// pose, measured as a component's [`ComponentFrame`] measures the component.
pub(crate) fn tight_extent(mesh: &TriMesh) -> f64 {
    tight_box_axes(mesh)
        .iter()
        .map(|&axis| {
            let (lo, hi) = projection_range(&mesh.positions, axis);
            hi - lo
        })
        .fold(0.0, f64::max)
}

/// For each frame, the index of the first frame it is a copy of (itself when none before it
/// is): the components whose V-HACD runs are the ones that map to themselves.
pub(crate) fn first_copies(frames: &[&ComponentFrame]) -> Vec<usize> {
    // Candidates share their triangle list; the vertices are compared only within that bucket.
    let mut by_triangles: HashMap<&[[u32; 3]], Vec<usize>> = HashMap::new();
    let mut first = Vec::with_capacity(frames.len());
    for (i, frame) in frames.iter().enumerate() {
        let bucket = by_triangles.entry(frame.triangles.as_slice()).or_default();
        match bucket.iter().find(|&&j| frames[j].same_shape(frame)) {
            Some(&j) => first.push(j),
            None => {
                bucket.push(i);
                first.push(i);
            }
        }
    }
    first
}

/// Corners of the surface voxels of a V-HACD part.
fn surface_voxel_corners(part: &VoxelSet) -> Vec<Vec3> {
    let mut corners = Vec::new();
    for voxel in part.voxels().iter().filter(|v| v.is_on_surface) {
        let centre = voxel.coords.as_vec3();
        for dz in [-0.5, 0.5] {
            for dy in [-0.5, 0.5] {
                for dx in [-0.5, 0.5] {
                    corners.push(part.origin + (centre + Vec3::new(dx, dy, dz)) * part.scale);
                }
            }
        }
    }
    corners
}
