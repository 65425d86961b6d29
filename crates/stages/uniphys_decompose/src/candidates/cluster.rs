//! Ward agglomerative clustering of per-face (or per-region) feature rows under face adjacency.
//!
//! The merge tree is built once with a heap and lazy deletion (O(E log E) for E adjacent
//! cluster pairs) and replayed with a union-find for every K. Merges inside a connected component
//! come before merges across components: a separate shell is a strong hint of a separate part,
//! so components are split only when K exceeds their count. Separate connected components are
//! linked to their nearest components by closest vertices (Kruskal over each component's nearest
//! neighbours by bounding-box gap), so the tree always reaches one cluster and a far-away piece
//! joins a near one rather than an arbitrary one.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::RangeInclusive;

use uniphys_geometry::{Aabb, DVec3, TriMesh};

use super::adjacency::{FaceAdjacency, UnionFind, welded_vertex_ids};
use super::{Candidate, relabel_by_first_face};
use crate::{DecomposeError, DecomposeResult};

/// Components with more members than this are linked by a spatial chain instead of nearest
/// neighbours (the pairwise box gaps would cost too much).
const MAX_COMPONENTS_FOR_NEAREST: usize = 2000;
/// Nearest components (by box gap) whose closest vertices are measured per component.
const NEAREST_COMPONENTS: usize = 4;
/// Vertices per component used to measure closest points.
const REPRESENTATIVES: usize = 48;

/// Ward clustering of one feature row per face (`features.len() == faces * dims`), connected by
/// shared edges; one candidate per K of `k_values` from 1 to the face count, ascending.
///
/// Faces are weighted by their area (a finely tessellated region does not outweigh a coarse one
/// of the same size). Features are used as given (normalise them first if their scale matters).
pub fn cluster_faces(
    mesh: &TriMesh,
    features: &[f32],
    dims: usize,
    k_values: RangeInclusive<usize>,
) -> DecomposeResult<Vec<Candidate>> {
    let regions: Vec<u32> = (0..u32::try_from(mesh.triangle_count()).unwrap_or(u32::MAX)).collect();
    cluster_regions(mesh, features, dims, &regions, k_values)
}

/// Like [`cluster_faces`], but faces with the same `regions` value start (and stay) together: the
/// tree is built over regions, so K is at most the region count.
pub fn cluster_regions(
    mesh: &TriMesh,
    features: &[f32],
    dims: usize,
    regions: &[u32],
    k_values: RangeInclusive<usize>,
) -> DecomposeResult<Vec<Candidate>> {
    let faces = mesh.triangle_count();
    if faces == 0 {
        return Err(DecomposeError::InvalidInput("the mesh has no faces".into()));
    }
    if dims == 0 || features.len() != faces * dims {
        return Err(DecomposeError::InvalidInput(format!(
            "{} feature values for {faces} faces x {dims} dimensions",
            features.len()
        )));
    }
    if regions.len() != faces {
        return Err(DecomposeError::InvalidInput(format!(
            "{} region labels for {faces} faces",
            regions.len()
        )));
    }
    if features.iter().any(|f| !f.is_finite()) {
        return Err(DecomposeError::InvalidInput(
            "a feature value is not finite".into(),
        ));
    }
    let (region_of_face, region_count) = relabel_by_first_face(regions);
    let welded = welded_vertex_ids(mesh);
    let adjacency = FaceAdjacency::new(mesh, &welded);

    // Region weights (area) and area-weighted mean features.
    let total_area = mesh.area();
    let floor = if total_area > 0.0 {
        1e-12 * total_area / faces as f64
    } else {
        1.0
    };
    let mut weight = vec![0.0f64; region_count];
    let mut centroid = vec![0.0f64; region_count * dims];
    for f in 0..faces {
        let r = region_of_face[f] as usize;
        let w = mesh.face_area(f).max(floor);
        weight[r] += w;
        for d in 0..dims {
            centroid[r * dims + d] += w * f64::from(features[f * dims + d]);
        }
    }
    for r in 0..region_count {
        for d in 0..dims {
            centroid[r * dims + d] /= weight[r];
        }
    }

    let mut links: Vec<(u32, u32)> = adjacency
        .pairs
        .iter()
        .map(|&(a, b)| (region_of_face[a as usize], region_of_face[b as usize]))
        .filter(|(a, b)| a != b)
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    let mut components = UnionFind::new(region_count);
    for &(a, b) in &links {
        components.union(a, b);
    }
    let component_of_region: Vec<u32> = (0..u32::try_from(region_count).unwrap_or(u32::MAX))
        .map(|r| components.find(r))
        .collect();
    links.extend(component_links(mesh, &region_of_face, region_count, &links));
    links.sort_unstable();
    links.dedup();

    let k_min = k_values.start().max(&1).to_owned();
    let tree = ward_tree(&weight, centroid, dims, &links, &component_of_region, k_min);
    let mut candidates = replay(&tree, &region_of_face, region_count, k_values.clone());
    if candidates.is_empty() && *k_values.start() > region_count {
        // Every K asked for is above the region count: the finest decomposition is the nearest.
        candidates = replay(
            &tree,
            &region_of_face,
            region_count,
            region_count..=region_count,
        );
    }
    Ok(candidates)
}

/// Merges in order, as pairs of region representatives (the smallest region of each cluster).
struct MergeTree {
    merges: Vec<(u32, u32)>,
}

/// Ward merges over `links`; merges inside a connected component (`component_of_region`) all come
/// before merges across components, so components split only when K exceeds their count.
fn ward_tree(
    weight: &[f64],
    mut centroid: Vec<f64>,
    dims: usize,
    links: &[(u32, u32)],
    component_of_region: &[u32],
    k_min: usize,
) -> MergeTree {
    let n = weight.len();
    let capacity = 2 * n;
    let mut weight = {
        let mut w = weight.to_vec();
        w.reserve(n);
        w
    };
    centroid.reserve(n * dims);
    let mut representative: Vec<u32> = (0..u32::try_from(n).unwrap_or(u32::MAX)).collect();
    let mut alive = vec![true; n];
    alive.reserve(n);
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); n];
    neighbours.reserve(n);
    // Components joined by merges so far; a cluster's component is that of its representative.
    let mut joined = UnionFind::new(n);
    let mut heap: BinaryHeap<Reverse<(u8, u64, u32, u32)>> = BinaryHeap::with_capacity(links.len());
    let ward = |weight: &[f64], centroid: &[f64], a: usize, b: usize| -> u64 {
        let (wa, wb) = (weight[a], weight[b]);
        let mut d2 = 0.0;
        for d in 0..dims {
            let diff = centroid[a * dims + d] - centroid[b * dims + d];
            d2 += diff * diff;
        }
        // Non-negative finite floats order like their bit patterns.
        (wa * wb / (wa + wb) * d2).to_bits()
    };
    let tier = |joined: &mut UnionFind, representative: &[u32], a: usize, b: usize| -> u8 {
        let ca = joined.find(component_of_region[representative[a] as usize]);
        let cb = joined.find(component_of_region[representative[b] as usize]);
        u8::from(ca != cb)
    };
    for &(a, b) in links {
        neighbours[a as usize].push(b);
        neighbours[b as usize].push(a);
        let t = tier(&mut joined, &representative, a as usize, b as usize);
        heap.push(Reverse((
            t,
            ward(&weight, &centroid, a as usize, b as usize),
            a,
            b,
        )));
    }
    let mut merges = Vec::new();
    let mut clusters = n;
    while clusters > k_min {
        let Some(Reverse((_, _, a, b))) = heap.pop() else {
            break;
        };
        let (a, b) = (a as usize, b as usize);
        if !alive[a] || !alive[b] {
            continue;
        }
        let m = weight.len();
        debug_assert!(m < capacity);
        let m_id = u32::try_from(m).unwrap_or(u32::MAX);
        let (wa, wb) = (weight[a], weight[b]);
        weight.push(wa + wb);
        for d in 0..dims {
            let c = (wa * centroid[a * dims + d] + wb * centroid[b * dims + d]) / (wa + wb);
            centroid.push(c);
        }
        alive[a] = false;
        alive[b] = false;
        alive.push(true);
        merges.push((representative[a], representative[b]));
        joined.union(
            component_of_region[representative[a] as usize],
            component_of_region[representative[b] as usize],
        );
        representative.push(representative[a].min(representative[b]));
        let mut around: Vec<u32> = std::mem::take(&mut neighbours[a]);
        around.append(&mut std::mem::take(&mut neighbours[b]));
        around.retain(|&x| alive[x as usize]);
        around.sort_unstable();
        around.dedup();
        for &x in &around {
            neighbours[x as usize].retain(|&y| alive[y as usize]);
            neighbours[x as usize].push(m_id);
            let t = tier(&mut joined, &representative, x as usize, m);
            heap.push(Reverse((
                t,
                ward(&weight, &centroid, x as usize, m),
                x,
                m_id,
            )));
        }
        neighbours.push(around);
        clusters -= 1;
    }
    MergeTree { merges }
}

fn replay(
    tree: &MergeTree,
    region_of_face: &[u32],
    region_count: usize,
    k_values: RangeInclusive<usize>,
) -> Vec<Candidate> {
    let mut uf = UnionFind::new(region_count);
    let mut out = Vec::new();
    let labels_now = |uf: &mut UnionFind| -> Vec<u32> {
        let roots: Vec<u32> = region_of_face.iter().map(|&r| uf.find(r)).collect();
        relabel_by_first_face(&roots).0
    };
    let mut clusters = region_count;
    let wanted = |clusters: usize, uf: &mut UnionFind, out: &mut Vec<Candidate>| {
        if clusters >= 1 && k_values.contains(&clusters) {
            out.push(Candidate {
                k: clusters,
                face_labels: labels_now(uf),
            });
        }
    };
    wanted(clusters, &mut uf, &mut out);
    for &(a, b) in &tree.merges {
        uf.union(a, b);
        clusters -= 1;
        wanted(clusters, &mut uf, &mut out);
    }
    out.reverse();
    out
}

/// Extra region links that join the connected components of the region graph: each component to
/// its nearest components (closest representative vertices), as a minimum spanning forest.
fn component_links(
    mesh: &TriMesh,
    region_of_face: &[u32],
    region_count: usize,
    links: &[(u32, u32)],
) -> Vec<(u32, u32)> {
    let mut uf = UnionFind::new(region_count);
    for &(a, b) in links {
        uf.union(a, b);
    }
    let roots: Vec<u32> = (0..u32::try_from(region_count).unwrap_or(u32::MAX))
        .map(|r| uf.find(r))
        .collect();
    let (component_of_region, components) = relabel_by_first_face(&roots);
    if components <= 1 {
        return Vec::new();
    }
    // Vertices of each component with the region of a face that uses them.
    let mut members: Vec<Vec<(u32, u32)>> = vec![Vec::new(); components];
    for (f, tri) in mesh.triangles.iter().enumerate() {
        let region = region_of_face[f];
        let c = component_of_region[region as usize] as usize;
        for &v in tri {
            members[c].push((v, region));
        }
    }
    let mut bounds = vec![Aabb::EMPTY; components];
    let mut reps: Vec<Vec<(DVec3, u32)>> = Vec::with_capacity(components);
    for (c, list) in members.iter_mut().enumerate() {
        list.sort_unstable();
        list.dedup_by_key(|e| e.0);
        for &(v, _) in list.iter() {
            bounds[c] = bounds[c].grown(mesh.positions[v as usize]);
        }
        let stride = list.len().div_ceil(REPRESENTATIVES).max(1);
        reps.push(
            list.iter()
                .step_by(stride)
                .map(|&(v, r)| (mesh.positions[v as usize], r))
                .collect(),
        );
    }
    // Candidate edges (tier, distance, component a, component b, region a, region b).
    let mut edges: Vec<(u8, u64, u32, u32, u32, u32)> = Vec::new();
    let closest = |a: usize, b: usize| -> (f64, u32, u32) {
        let mut best = (f64::INFINITY, 0, 0);
        for &(pa, ra) in &reps[a] {
            for &(pb, rb) in &reps[b] {
                let d = pa.distance_squared(pb);
                if d < best.0 {
                    best = (d, ra, rb);
                }
            }
        }
        best
    };
    let id = |c: usize| u32::try_from(c).unwrap_or(u32::MAX);
    if components <= MAX_COMPONENTS_FOR_NEAREST {
        for a in 0..components {
            let mut near: Vec<(u64, usize)> = (0..components)
                .filter(|&b| b != a)
                .map(|b| (box_gap(&bounds[a], &bounds[b]).to_bits(), b))
                .collect();
            let keep = NEAREST_COMPONENTS.min(near.len());
            near.select_nth_unstable(keep - 1);
            for &(_, b) in &near[..keep] {
                let (d, ra, rb) = closest(a, b);
                edges.push((0, d.to_bits(), id(a.min(b)), id(a.max(b)), ra, rb));
            }
        }
    }
    // A spatial chain (components ordered along the longest axis of their centres) guarantees
    // that the forest below spans everything; its edges are only used where nearer ones are
    // missing.
    let centres: Vec<DVec3> = bounds.iter().map(Aabb::center).collect();
    let span = Aabb::from_points(centres.iter()).extents();
    let axis = if span.x >= span.y && span.x >= span.z {
        0
    } else if span.y >= span.z {
        1
    } else {
        2
    };
    let mut order: Vec<usize> = (0..components).collect();
    order.sort_by(|&a, &b| {
        centres[a][axis]
            .total_cmp(&centres[b][axis])
            .then(a.cmp(&b))
    });
    for w in order.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (d, ra, rb) = closest(a, b);
        // Chain edges (tier 1) rank after every nearest-neighbour edge.
        edges.push((1, d.to_bits(), id(a.min(b)), id(a.max(b)), ra, rb));
    }
    edges.sort_unstable();
    let mut forest = UnionFind::new(components);
    let mut out = Vec::new();
    for (_, _, a, b, ra, rb) in edges {
        if forest.union(a, b) {
            out.push((ra.min(rb), ra.max(rb)));
        }
    }
    out
}

/// Distance between two boxes (0 when they overlap).
fn box_gap(a: &Aabb, b: &Aabb) -> f64 {
    let gap = (a.min - b.max).max(b.min - a.max).max(DVec3::ZERO);
    gap.length()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit boxes side by side along x with a gap, plus a far third box.
    fn three_boxes() -> TriMesh {
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::new(1.1, 0.0, 0.0), DVec3::new(2.1, 1.0, 1.0));
        let c = TriMesh::cuboid(DVec3::new(10.0, 0.0, 0.0), DVec3::new(11.0, 1.0, 1.0));
        TriMesh::merge([&a, &b, &c])
    }

    fn position_features(mesh: &TriMesh) -> Vec<f32> {
        (0..mesh.triangle_count())
            .flat_map(|f| {
                let [a, b, c] = mesh.corners(f);
                ((a + b + c) / 3.0).to_array().map(|x| x as f32)
            })
            .collect()
    }

    #[test]
    fn every_k_is_a_coarsening_of_the_next_and_labels_are_compact() {
        let mesh = three_boxes();
        let features = position_features(&mesh);
        let candidates = cluster_faces(&mesh, &features, 3, 1..=36).unwrap();
        assert_eq!(candidates.len(), 36);
        for (i, c) in candidates.iter().enumerate() {
            assert_eq!(c.k, i + 1);
            let max = *c.face_labels.iter().max().unwrap() as usize;
            assert_eq!(max + 1, c.k);
            assert_eq!(c.face_labels[0], 0);
        }
        // Nested: faces together at K+1 are together at K.
        for pair in candidates.windows(2) {
            let (coarse, fine) = (&pair[0].face_labels, &pair[1].face_labels);
            for f in 0..fine.len() {
                for g in 0..fine.len() {
                    if fine[f] == fine[g] {
                        assert_eq!(coarse[f], coarse[g]);
                    }
                }
            }
        }
    }

    #[test]
    fn three_boxes_at_k3_are_the_boxes_and_the_near_pair_joins_first() {
        let mesh = three_boxes();
        let features = position_features(&mesh);
        let candidates = cluster_faces(&mesh, &features, 3, 2..=3).unwrap();
        let k3 = &candidates[1].face_labels;
        let expected: Vec<u32> = (0..36).map(|f| f / 12).collect();
        assert_eq!(k3, &expected);
        let k2 = &candidates[0].face_labels;
        let expected: Vec<u32> = (0..36).map(|f| u32::from(f >= 24)).collect();
        assert_eq!(k2, &expected);
    }

    #[test]
    fn components_split_only_after_every_component_is_whole() {
        // Two boxes far apart, each cut into 6 side regions whose features pull the two tops
        // together: still, K = 2 is the two boxes, and K = 3 splits inside one box.
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::new(1.5, 0.0, 0.0), DVec3::new(2.5, 1.0, 1.0));
        let mesh = TriMesh::merge([&a, &b]);
        let regions: Vec<u32> = (0..24).map(|f| f / 2).collect();
        // Feature: only "is a top face" (z normal up), so without the component rule the two tops
        // (identical features) would merge first.
        let features: Vec<f32> = (0..24)
            .map(|f| {
                if mesh.face_normal(f).z > 0.5 {
                    10.0
                } else {
                    0.0
                }
            })
            .collect();
        let candidates = cluster_regions(&mesh, &features, 1, &regions, 2..=3).unwrap();
        let expected: Vec<u32> = (0..24).map(|f| u32::from(f >= 12)).collect();
        assert_eq!(candidates[0].face_labels, expected);
        let k3 = &candidates[1].face_labels;
        assert!((0..12).all(|f| k3[f] == k3[0]) || (12..24).all(|f| k3[f] == k3[12]));
        // A range entirely above the region count gives the finest decomposition.
        let finest = cluster_regions(&mesh, &features, 1, &regions, 20..=30).unwrap();
        assert_eq!(finest.len(), 1);
        assert_eq!(finest[0].k, 12);
    }

    #[test]
    fn regions_stay_together_and_bad_input_is_refused() {
        let mesh = three_boxes();
        let features = position_features(&mesh);
        let regions: Vec<u32> = (0..36).map(|f| f / 6).collect();
        let candidates = cluster_regions(&mesh, &features, 3, &regions, 1..=10).unwrap();
        assert_eq!(candidates.last().unwrap().k, 6);
        for c in &candidates {
            for f in 0..36 {
                assert_eq!(c.face_labels[f], c.face_labels[f - f % 6]);
            }
        }
        assert!(cluster_faces(&mesh, &features[1..], 3, 1..=2).is_err());
        assert!(cluster_faces(&TriMesh::default(), &[], 3, 1..=2).is_err());
    }
}
