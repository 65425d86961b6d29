//! Candidate decompositions for every part count K in a range.
//!
//! A [`CandidateGenerator`] turns a mesh into one face labelling per K: the built-in
//! [`GeometricGenerator`] (Ward clustering of connected components and crease regions over
//! position, normal and colour features), or a PartField-compatible feature service whose
//! per-face features go through the same [`cluster_faces`].

pub mod adjacency;
pub mod cluster;
pub mod geometric;
pub mod remote;

use std::ops::RangeInclusive;

use uniphys_geometry::TriMesh;

use crate::DecomposeResult;

pub use adjacency::{FaceAdjacency, UnionFind, welded_vertex_ids};
pub use cluster::{cluster_faces, cluster_regions};
pub use geometric::{GeometricGenerator, GeometricOptions};
pub use remote::PartFieldGenerator;

/// One decomposition of the mesh into `k` parts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Candidate {
    /// Number of parts.
    pub k: usize,
    /// Part label of every face, `0..k`, numbered in the order of each part's smallest face.
    pub face_labels: Vec<u32>,
}

/// What a generator is asked for.
#[derive(Debug, Clone)]
pub struct CandidateRequest<'a> {
    /// The merged mesh.
    pub mesh: &'a TriMesh,
    /// Colour of every face (RGBA, sRGB bytes).
    pub face_rgba: &'a [[u8; 4]],
    /// Material index of every face.
    pub face_material: &'a [u32],
    /// The part counts wanted; counts the generator cannot reach are left out.
    pub k_values: RangeInclusive<usize>,
    /// Seed for anything random.
    pub seed: u64,
}

/// A source of candidate decompositions.
pub trait CandidateGenerator: Send + Sync {
    /// Who produced the candidates, e.g. "builtin-geometric-clustering" or `partfield:<model>`.
    fn provider(&self) -> String;
    /// One candidate per reachable K of the request, ascending K.
    fn candidates(&self, request: &CandidateRequest<'_>) -> DecomposeResult<Vec<Candidate>>;
    /// Whether the candidates come from learned per-face features, whose cuts inside one
    /// connected piece of the mesh are evidence (a welded door); geometric clustering's cuts
    /// inside a piece follow creases and are not, so the stage makes those pieces whole.
    fn learned(&self) -> bool {
        false
    }
}

/// Labels renumbered `0..k` in the order of first appearance (so by each group's smallest face);
/// returns the labels and k.
#[must_use]
pub fn relabel_by_first_face(labels: &[u32]) -> (Vec<u32>, usize) {
    let mut map: std::collections::BTreeMap<u32, u32> = std::collections::BTreeMap::new();
    let out = labels
        .iter()
        .map(|&l| {
            let next = u32::try_from(map.len()).unwrap_or(u32::MAX);
            *map.entry(l).or_insert(next)
        })
        .collect();
    (out, map.len())
}
