use std::collections::HashMap;

use crate::TriMesh;

/// Triangles of `mesh` grouped into connected components: two triangles are connected when they
/// share a vertex after welding vertices by position (tolerance 1e-9 times the bounds diagonal).
///
/// Each component lists its triangle indices ascending; components are ordered by their
/// smallest triangle index.
#[must_use]
pub fn connected_components(mesh: &TriMesh) -> Vec<Vec<usize>> {
    let weld = weld_map(mesh);
    let mut parent: Vec<usize> = (0..mesh.positions.len()).collect();
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|v| weld[v as usize]);
        union(&mut parent, a, b);
        union(&mut parent, a, c);
    }
    let mut component_of_root: HashMap<usize, usize> = HashMap::new();
    let mut components: Vec<Vec<usize>> = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let root = find(&mut parent, weld[tri[0] as usize]);
        let next = components.len();
        let c = *component_of_root.entry(root).or_insert(next);
        if c == next {
            components.push(Vec::new());
        }
        components[c].push(t);
    }
    components
}

/// For each vertex, the index of the first vertex at the same position (quantised to 1e-9 of
/// the bounds diagonal, like [`TriMesh::welded`]).
fn weld_map(mesh: &TriMesh) -> Vec<usize> {
    let diagonal = mesh.bounds().diagonal();
    let inv = if diagonal > 0.0 && diagonal.is_finite() {
        1.0 / (1e-9 * diagonal)
    } else {
        1.0
    };
    let mut first_at: HashMap<[i64; 3], usize> = HashMap::with_capacity(mesh.positions.len());
    mesh.positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let key = (*p * inv).round().to_array().map(|c| c as i64);
            *first_at.entry(key).or_insert(i)
        })
        .collect()
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        // The smaller index becomes the root, so roots do not depend on union order.
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        parent[hi] = lo;
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::test_shapes::{two_boxes, unit_box};

    #[test]
    fn two_disjoint_boxes_are_two_components() {
        let components = connected_components(&two_boxes());
        assert_eq!(
            components,
            vec![(0..12).collect::<Vec<_>>(), (12..24).collect()]
        );
    }

    #[test]
    fn a_box_split_at_seams_is_still_one_component() {
        let m = unit_box(DVec3::ZERO, DVec3::ONE);
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for i in 0..m.triangle_count() {
            let base = u32::try_from(positions.len()).unwrap();
            positions.extend(m.corners(i));
            triangles.push([base, base + 1, base + 2]);
        }
        let split = TriMesh::new(positions, triangles).unwrap();
        assert_eq!(
            connected_components(&split),
            vec![(0..12).collect::<Vec<_>>()]
        );
    }

    #[test]
    fn components_are_ordered_by_their_first_triangle() {
        // Interleave the triangles of two far apart triangles pairs: 0 and 2 share vertices,
        // 1 and 3 share vertices.
        let mesh = TriMesh::new(
            vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::Y,
                DVec3::new(5.0, 0.0, 0.0),
                DVec3::new(6.0, 0.0, 0.0),
                DVec3::new(5.0, 1.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(6.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [3, 4, 5], [1, 6, 2], [4, 7, 5]],
        )
        .unwrap();
        assert_eq!(connected_components(&mesh), vec![vec![0, 2], vec![1, 3]]);
        assert!(connected_components(&TriMesh::default()).is_empty());
    }
}
