//! Face adjacency of a triangle soup: vertices welded by position, faces adjacent when they share
//! an edge.

use uniphys_geometry::TriMesh;

/// Welding tolerance as a fraction of the bounds diagonal.
const WELD_TOLERANCE_REL: f64 = 1e-7;

/// For every vertex, a welded id: vertices at the same position (quantised to 1e-7 of the bounds
/// diagonal) share the id; ids are numbered by first appearance, so the result depends only on
/// the input.
#[must_use]
pub fn welded_vertex_ids(mesh: &TriMesh) -> Vec<u32> {
    let diagonal = mesh.bounds().diagonal();
    let inv = if diagonal > 0.0 && diagonal.is_finite() {
        1.0 / (WELD_TOLERANCE_REL * diagonal)
    } else {
        1.0
    };
    #[expect(
        clippy::cast_possible_truncation,
        reason = "quantised key of a bounded coordinate"
    )]
    let keys: Vec<[i64; 3]> = mesh
        .positions
        .iter()
        .map(|p| (*p * inv).round().to_array().map(|c| c as i64))
        .collect();
    let mut order: Vec<u32> = (0..u32::try_from(keys.len()).unwrap_or(u32::MAX)).collect();
    order.sort_by_key(|&i| (keys[i as usize], i));
    let mut ids = vec![0u32; keys.len()];
    let mut run_start = 0;
    for j in 1..=order.len() {
        if j == order.len() || keys[order[j] as usize] != keys[order[run_start] as usize] {
            // All vertices of the run take the smallest vertex index as their id.
            let id = order[run_start];
            for &v in &order[run_start..j] {
                ids[v as usize] = id;
            }
            run_start = j;
        }
    }
    ids
}

/// The edges of a mesh over welded vertices, each with the faces using it: faces over the same
/// three welded vertices (the two sides of a double-sided surface) count once, their first
/// standing for all, and a face over fewer has none. Listed once, read by the manifold split
/// and the pocket search alike.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct WeldedEdges {
    /// Edges `(u, v, face)` over welded vertex ids `u < v`, sorted.
    pub edges: Vec<(u32, u32, u32)>,
    /// For each face, the face that stands for it (itself, or the first over the same three
    /// welded vertices).
    pub stands_for: Vec<u32>,
}

impl WeldedEdges {
    /// The welded edges of `mesh`; `welded` from [`welded_vertex_ids`].
    #[must_use]
    pub fn new(mesh: &TriMesh, welded: &[u32]) -> Self {
        let mut keyed: Vec<([u32; 3], u32)> = mesh
            .triangles
            .iter()
            .enumerate()
            .map(|(f, t)| {
                let mut key = t.map(|v| welded[v as usize]);
                key.sort_unstable();
                (key, u32::try_from(f).unwrap_or(u32::MAX))
            })
            .collect();
        keyed.sort_unstable();
        let mut stands_for: Vec<u32> =
            (0..u32::try_from(keyed.len()).unwrap_or(u32::MAX)).collect();
        let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(keyed.len() * 3);
        for (i, &(key, f)) in keyed.iter().enumerate() {
            if i > 0 && keyed[i - 1].0 == key {
                stands_for[f as usize] = stands_for[keyed[i - 1].1 as usize];
                continue;
            }
            let [a, b, c] = key;
            // A face over fewer than three welded vertices has no area and no edges of its own.
            if a != b && b != c {
                edges.extend([(a, b, f), (b, c, f), (a, c, f)]);
            }
        }
        edges.sort_unstable();
        Self { edges, stands_for }
    }

    /// Runs of edges over the same two vertices: the faces around each edge.
    pub fn runs(&self) -> impl Iterator<Item = &[(u32, u32, u32)]> {
        self.edges.chunk_by(|a, b| a.0 == b.0 && a.1 == b.1)
    }
}

/// A face pair, its shared welded edge and whether the edge is manifold.
type FoundPair = ((u32, u32), (u32, u32), bool);

/// Faces that share an edge (after welding), each pair once with the smaller face first,
/// sorted; `edges[i]` is the welded edge the pair `pairs[i]` shares.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FaceAdjacency {
    /// Adjacent face pairs `(a, b)` with `a < b`, sorted.
    pub pairs: Vec<(u32, u32)>,
    /// The welded vertex ids of the shared edge of each pair.
    pub edges: Vec<(u32, u32)>,
    /// Whether the shared edge has exactly these two faces (more faces on one edge is where
    /// separate pieces touch).
    pub manifold: Vec<bool>,
}

impl FaceAdjacency {
    /// Adjacency of all faces of `mesh`; `welded` from [`welded_vertex_ids`]. On an edge shared by
    /// more than two faces every face is linked to the first one.
    #[must_use]
    pub fn new(mesh: &TriMesh, welded: &[u32]) -> Self {
        let mut half: Vec<((u32, u32), u32)> = Vec::with_capacity(mesh.triangles.len() * 3);
        for (f, tri) in mesh.triangles.iter().enumerate() {
            let w = tri.map(|v| welded[v as usize]);
            let face = u32::try_from(f).unwrap_or(u32::MAX);
            for (a, b) in [(w[0], w[1]), (w[1], w[2]), (w[2], w[0])] {
                if a != b {
                    half.push(((a.min(b), a.max(b)), face));
                }
            }
        }
        half.sort_unstable();
        let mut found: Vec<FoundPair> = Vec::new();
        let mut start = 0;
        for j in 1..=half.len() {
            if j == half.len() || half[j].0 != half[start].0 {
                let first = half[start].1;
                let manifold = j - start == 2;
                for item in &half[start + 1..j] {
                    if item.1 != first {
                        found.push((
                            (first.min(item.1), first.max(item.1)),
                            half[start].0,
                            manifold,
                        ));
                    }
                }
                start = j;
            }
        }
        found.sort_unstable();
        found.dedup_by_key(|e| e.0);
        Self {
            pairs: found.iter().map(|e| e.0).collect(),
            edges: found.iter().map(|e| e.1).collect(),
            manifold: found.iter().map(|e| e.2).collect(),
        }
    }
}

/// A union-find over `0..n` whose roots are the smallest member, so results do not depend on the
/// order of unions.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` singletons.
    #[must_use]
    pub fn new(n: usize) -> Self {
        Self {
            parent: (0..u32::try_from(n).unwrap_or(u32::MAX)).collect(),
        }
    }

    /// The root (smallest member) of `x`'s set.
    pub fn find(&mut self, x: u32) -> u32 {
        let mut root = x;
        while self.parent[root as usize] != root {
            root = self.parent[root as usize];
        }
        let mut y = x;
        while self.parent[y as usize] != root {
            let next = self.parent[y as usize];
            self.parent[y as usize] = root;
            y = next;
        }
        root
    }

    /// Joins the sets of `a` and `b`; whether they were apart.
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        self.parent[hi as usize] = lo;
        true
    }
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;

    #[test]
    fn a_box_has_eighteen_shared_edges_and_welding_joins_split_vertices() {
        let cube = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let welded = welded_vertex_ids(&cube);
        let adjacency = FaceAdjacency::new(&cube, &welded);
        // 12 triangles x 3 edges / 2 = 18 edges, each shared by two faces.
        assert_eq!(adjacency.pairs.len(), 18);
        assert!(adjacency.manifold.iter().all(|&m| m));
        // The same box with every triangle on its own vertices: same adjacency.
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for i in 0..cube.triangle_count() {
            let base = u32::try_from(positions.len()).unwrap();
            positions.extend(cube.corners(i));
            triangles.push([base, base + 1, base + 2]);
        }
        let soup = TriMesh::new(positions, triangles).unwrap();
        let soup_adjacency = FaceAdjacency::new(&soup, &welded_vertex_ids(&soup));
        assert_eq!(soup_adjacency.pairs, adjacency.pairs);
    }

    #[test]
    fn union_find_roots_are_smallest_members() {
        let mut uf = UnionFind::new(6);
        assert!(uf.union(4, 2));
        assert!(uf.union(5, 4));
        assert!(!uf.union(2, 5));
        assert_eq!(uf.find(5), 2);
        assert_eq!(uf.find(3), 3);
    }
}
