//! Connectivity refinement (reference §3.6a/c with a relative distance): every part is split into
//! its connected pieces, where vertices are connected by triangle edges and by being closer than
//! `eps_rel` times the object diagonal (so parts that are modelled as several touching shells stay
//! whole).

use uniphys_geometry::TriMesh;

use crate::candidates::{UnionFind, relabel_by_first_face, welded_vertex_ids};

/// Splits every part of `face_part` into its connected pieces. With `keep_whole_above`, a part
/// that would fall into more pieces than that is kept whole (a part made of many loose bits, like
/// a grille, is one part). Returns the new labels (numbered by smallest face) and their count.
#[must_use]
pub fn split_disconnected(
    mesh: &TriMesh,
    face_part: &[u32],
    eps_rel: f64,
    keep_whole_above: Option<usize>,
) -> (Vec<u32>, usize) {
    let eps_m = eps_rel * mesh.bounds().diagonal();
    let welded = welded_vertex_ids(mesh);
    let parts = face_part.iter().max().map_or(0, |&m| m as usize + 1);
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); parts];
    for (f, &p) in face_part.iter().enumerate() {
        faces_of[p as usize].push(f);
    }
    // Local index of each welded vertex inside the current part (u32::MAX: not in it).
    let mut local = vec![u32::MAX; mesh.positions.len()];
    let mut piece = vec![0u32; face_part.len()];
    let mut next_label = 0u32;
    for faces in &faces_of {
        let mut vertices: Vec<u32> = Vec::new();
        for &f in faces {
            for &v in &mesh.triangles[f] {
                let w = welded[v as usize];
                if local[w as usize] == u32::MAX {
                    local[w as usize] = u32::try_from(vertices.len()).unwrap_or(u32::MAX);
                    vertices.push(w);
                }
            }
        }
        let mut uf = UnionFind::new(vertices.len());
        for &f in faces {
            let [a, b, c] = mesh.triangles[f].map(|v| local[welded[v as usize] as usize]);
            uf.union(a, b);
            uf.union(a, c);
        }
        let first = uf.find(0);
        let one_piece =
            (0..u32::try_from(vertices.len()).unwrap_or(u32::MAX)).all(|v| uf.find(v) == first);
        if eps_m > 0.0 && !one_piece {
            join_close(mesh, &vertices, eps_m, &mut uf);
        }
        let roots: Vec<u32> = faces
            .iter()
            .map(|&f| uf.find(local[welded[mesh.triangles[f][0] as usize] as usize]))
            .collect();
        let (pieces, count) = relabel_by_first_face(&roots);
        let whole = keep_whole_above.is_some_and(|limit| count > limit);
        for (&f, &p) in faces.iter().zip(&pieces) {
            piece[f] = next_label + if whole { 0 } else { p };
        }
        next_label += if whole {
            1
        } else {
            u32::try_from(count).unwrap_or(u32::MAX)
        };
        for &w in &vertices {
            local[w as usize] = u32::MAX;
        }
    }
    relabel_by_first_face(&piece)
}

/// Unions the vertices (local indices into `vertices`) closer than `eps_m`, with a sorted grid of
/// cell size `eps_m`.
fn join_close(mesh: &TriMesh, vertices: &[u32], eps_m: f64, uf: &mut UnionFind) {
    #[expect(
        clippy::cast_possible_truncation,
        reason = "grid cell of a bounded coordinate"
    )]
    let cell = |i: usize| -> [i64; 3] {
        (mesh.positions[vertices[i] as usize] / eps_m)
            .floor()
            .to_array()
            .map(|c| c as i64)
    };
    let mut sorted: Vec<([i64; 3], u32)> = (0..vertices.len())
        .map(|i| (cell(i), u32::try_from(i).unwrap_or(u32::MAX)))
        .collect();
    sorted.sort_unstable();
    // Cells with the range of `sorted` they hold.
    let mut cells: Vec<([i64; 3], usize, usize)> = Vec::new();
    for (at, &(c, _)) in sorted.iter().enumerate() {
        match cells.last_mut() {
            Some(last) if last.0 == c => last.2 = at + 1,
            _ => cells.push((c, at, at + 1)),
        }
    }
    let eps2 = eps_m * eps_m;
    for &(c, lo, hi) in &cells {
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                    // Each pair of cells once.
                    if key < c {
                        continue;
                    }
                    let Ok(n) = cells.binary_search_by(|e| e.0.cmp(&key)) else {
                        continue;
                    };
                    let (_, nlo, nhi) = cells[n];
                    // Nothing to join when both cells already lie in one piece.
                    let root = uf.find(sorted[lo].1);
                    let joined = sorted[lo..hi]
                        .iter()
                        .chain(&sorted[nlo..nhi])
                        .all(|&(_, v)| uf.find(v) == root);
                    if joined {
                        continue;
                    }
                    for &(_, i) in &sorted[lo..hi] {
                        let p = mesh.positions[vertices[i as usize] as usize];
                        for &(_, j) in &sorted[nlo..nhi] {
                            if i != j
                                && uf.find(i) != uf.find(j)
                                && p.distance_squared(mesh.positions[vertices[j as usize] as usize])
                                    <= eps2
                            {
                                uf.union(i, j);
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;

    fn cube(x: f64) -> TriMesh {
        TriMesh::cuboid(DVec3::new(x, 0.0, 0.0), DVec3::new(x + 1.0, 1.0, 1.0))
    }

    #[test]
    fn a_part_of_two_far_boxes_splits_and_near_shells_stay_together() {
        // Part 0: boxes at x = 0 and x = 3; part 1: boxes at x = 5 and x = 6.001 (a hair apart).
        let mesh = TriMesh::merge([&cube(0.0), &cube(3.0), &cube(5.0), &cube(6.001)]);
        let labels: Vec<u32> = (0..48).map(|f| u32::from(f >= 24)).collect();
        let (split, count) = split_disconnected(&mesh, &labels, 5e-3, None);
        assert_eq!(count, 3);
        let expected: Vec<u32> = (0..48).map(|f| [0, 1, 2, 2][f / 12]).collect();
        assert_eq!(split, expected);
        // With a tiny eps the near pair splits too.
        assert_eq!(split_disconnected(&mesh, &labels, 1e-6, None).1, 4);
        // Keep whole a part that would fall into more than one piece.
        assert_eq!(split_disconnected(&mesh, &labels, 1e-6, Some(1)).1, 2);
    }
}
