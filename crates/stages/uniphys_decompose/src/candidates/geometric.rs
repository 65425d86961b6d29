//! The built-in candidate generator: Ward clustering of mesh regions over position, normal,
//! colour and material features.
//!
//! Regions: every connected component is one region, except that a big component (a sizeable
//! share of the surface) is cut along concave creases and colour or material changes, which is
//! where parts of a one-piece mesh meet. Regions never split further, so a fragment is never
//! divided, and the clustering only decides which regions belong together.

use uniphys_geometry::{DVec3, SplitMix64, TriMesh};

use super::adjacency::{FaceAdjacency, UnionFind, welded_vertex_ids};
use super::cluster::cluster_regions;
use super::{Candidate, CandidateGenerator, CandidateRequest};
use crate::{DecomposeError, DecomposeResult};

/// Tuning of [`GeometricGenerator`]. Distances are fractions of the bounds diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct GeometricOptions {
    /// Weight of the face centre (divided by the bounds diagonal). Default 1.
    pub position_weight: f64,
    /// Weight of the unit face normal. Default 0.3.
    pub normal_weight: f64,
    /// Weight of the RGB colour in [0, 1]. Default 0.5.
    pub colour_weight: f64,
    /// Weight of a per-material random unit vector (different materials are about
    /// `sqrt(2)` times this apart). Default 0.5.
    pub material_weight: f64,
    /// A component with at least this share of the surface area is cut into regions. Default 0.1.
    pub big_component_area_fraction: f64,
    /// A shared edge is a concave crease when the faces' normals differ by more than this,
    /// radians. Default 30 degrees.
    pub crease_angle_rad: f64,
    /// Colours (RGB in [0, 1]) farther apart than this are a colour change. Default 0.15.
    pub colour_change: f64,
}

impl Default for GeometricOptions {
    fn default() -> Self {
        Self {
            position_weight: 1.0,
            normal_weight: 0.3,
            colour_weight: 0.5,
            material_weight: 0.5,
            big_component_area_fraction: 0.1,
            crease_angle_rad: 30f64.to_radians(),
            colour_change: 0.15,
        }
    }
}

/// The built-in generator, provider "builtin-geometric-clustering".
#[derive(Debug, Clone, Default)]
pub struct GeometricGenerator {
    /// Its options.
    pub options: GeometricOptions,
}

/// Feature dimensions per face: position, normal, colour, material.
const DIMS: usize = 12;

impl CandidateGenerator for GeometricGenerator {
    fn provider(&self) -> String {
        "builtin-geometric-clustering".to_owned()
    }

    fn candidates(&self, request: &CandidateRequest<'_>) -> DecomposeResult<Vec<Candidate>> {
        let mesh = request.mesh;
        let faces = mesh.triangle_count();
        if request.face_rgba.len() != faces || request.face_material.len() != faces {
            return Err(DecomposeError::InvalidInput(format!(
                "{faces} faces but {} colours and {} materials",
                request.face_rgba.len(),
                request.face_material.len()
            )));
        }
        let regions = regions(
            mesh,
            request.face_rgba,
            request.face_material,
            &self.options,
        );
        let features = face_features(mesh, request, &self.options);
        cluster_regions(mesh, &features, DIMS, &regions, request.k_values.clone())
    }
}

fn rgb(c: [u8; 4]) -> DVec3 {
    DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])) / 255.0
}

fn face_centre(mesh: &TriMesh, f: usize) -> DVec3 {
    let [a, b, c] = mesh.corners(f);
    (a + b + c) / 3.0
}

/// Region of every face (any ids): components, big ones cut at concave creases, colour or
/// material changes and edges shared by more than two faces.
#[must_use]
pub fn regions(
    mesh: &TriMesh,
    face_rgba: &[[u8; 4]],
    face_material: &[u32],
    options: &GeometricOptions,
) -> Vec<u32> {
    let faces = mesh.triangle_count();
    let adjacency = FaceAdjacency::new(mesh, &welded_vertex_ids(mesh));
    let mut components = UnionFind::new(faces);
    for &(a, b) in &adjacency.pairs {
        components.union(a, b);
    }
    let total_area = mesh.area();
    let mut component_area = vec![0.0f64; faces];
    for f in 0..faces {
        let root = components.find(u32::try_from(f).unwrap_or(u32::MAX)) as usize;
        component_area[root] += mesh.face_area(f);
    }
    let cos_crease = options.crease_angle_rad.cos();
    let mut out = UnionFind::new(faces);
    for (&(a, b), &manifold) in adjacency.pairs.iter().zip(&adjacency.manifold) {
        let (fa, fb) = (a as usize, b as usize);
        let root = components.find(a) as usize;
        let big = component_area[root] >= options.big_component_area_fraction * total_area;
        if big {
            if !manifold {
                // Pieces that touch along an edge (a lid on a box) are separate regions.
                continue;
            }
            if face_material[fa] != face_material[fb]
                || rgb(face_rgba[fa]).distance(rgb(face_rgba[fb])) > options.colour_change
            {
                continue;
            }
            let (na, nb) = (mesh.face_normal(fa), mesh.face_normal(fb));
            let towards_b = face_centre(mesh, fb) - face_centre(mesh, fa);
            // Concave: each face lies in front of the other's plane.
            let concave = towards_b.dot(na) > 0.0 && (-towards_b).dot(nb) > 0.0;
            if concave && na.dot(nb) < cos_crease {
                continue;
            }
        }
        out.union(a, b);
    }
    (0..u32::try_from(faces).unwrap_or(u32::MAX))
        .map(|f| out.find(f))
        .collect()
}

fn face_features(
    mesh: &TriMesh,
    request: &CandidateRequest<'_>,
    options: &GeometricOptions,
) -> Vec<f32> {
    let diagonal = mesh.bounds().diagonal().max(f64::MIN_POSITIVE);
    // A unit vector per material, deterministic for the seed.
    let mut materials: Vec<u32> = request.face_material.to_vec();
    materials.sort_unstable();
    materials.dedup();
    let mut rng = SplitMix64::new(request.seed ^ 0x6d61_7465_7269_616c);
    let embedding: Vec<DVec3> = materials
        .iter()
        .map(|_| {
            DVec3::new(
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            )
            .normalize_or(DVec3::X)
        })
        .collect();
    let mut features = Vec::with_capacity(mesh.triangle_count() * DIMS);
    for f in 0..mesh.triangle_count() {
        let position = face_centre(mesh, f) / diagonal * options.position_weight;
        let normal = mesh.face_normal(f) * options.normal_weight;
        let colour = rgb(request.face_rgba[f]) * options.colour_weight;
        let index = materials
            .binary_search(&request.face_material[f])
            .unwrap_or(0);
        let material = embedding[index] * options.material_weight;
        for v in [position, normal, colour, material] {
            #[expect(clippy::cast_possible_truncation, reason = "features are f32 rows")]
            features.extend(v.to_array().map(|x| x as f32));
        }
    }
    features
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_with_a_separate_lid_comes_out_as_two_parts_at_k2() {
        let body = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.8));
        let lid = TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.81), DVec3::new(1.0, 1.0, 1.0));
        let mesh = TriMesh::merge([&body, &lid]);
        let faces = mesh.triangle_count();
        let colours = vec![[200, 200, 200, 255]; faces];
        let materials = vec![0; faces];
        let request = CandidateRequest {
            mesh: &mesh,
            face_rgba: &colours,
            face_material: &materials,
            k_values: 1..=5,
            seed: 1,
        };
        let candidates = GeometricGenerator::default().candidates(&request).unwrap();
        // The boxes are convex components: two regions, so K is at most 2.
        assert_eq!(
            candidates.iter().map(|c| c.k).collect::<Vec<_>>(),
            vec![1, 2]
        );
        let expected: Vec<u32> = (0..faces).map(|f| u32::from(f >= 12)).collect();
        assert_eq!(candidates[1].face_labels, expected);
    }

    #[test]
    fn boxes_touching_along_edges_are_cut_where_they_touch() {
        let body = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.8));
        let lid = TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.8), DVec3::ONE);
        let mesh = TriMesh::merge([&body, &lid]);
        let r = regions(&mesh, &[[0; 4]; 24], &[0; 24], &GeometricOptions::default());
        // No region holds faces of both boxes.
        for f in 0..12 {
            for g in 12..24 {
                assert_ne!(r[f], r[g], "faces {f} and {g}");
            }
        }
        // The body's bottom and sides stay one region.
        let body_rest: Vec<u32> = (0..12)
            .filter(|f| !(2..4).contains(f))
            .map(|f| r[f])
            .collect();
        assert!(body_rest.iter().all(|&x| x == body_rest[0]));
    }

    #[test]
    fn a_big_component_is_cut_at_material_changes() {
        let mesh = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let colours = vec![[10, 10, 10, 255]; 12];
        // Top face (triangles 2 and 3) is another material.
        let materials: Vec<u32> = (0..12).map(|f| u32::from(f == 2 || f == 3)).collect();
        let r = regions(&mesh, &colours, &materials, &GeometricOptions::default());
        assert_eq!(r[2], r[3]);
        assert_ne!(r[2], r[0]);
        let others: Vec<u32> = (0..12)
            .filter(|&f| f != 2 && f != 3)
            .map(|f| r[f])
            .collect();
        assert!(others.iter().all(|&x| x == others[0]));
    }
}
