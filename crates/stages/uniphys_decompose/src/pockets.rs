//! Parts modelled into a surface: a knob or a button drawn as a bump of the panel's own surface,
//! or a cap drawn onto its bottle's neck, shares the edges of what it sits on (no seam, no edge
//! of three faces sets it apart), but it meets it along a crease, and everything of it lies
//! behind that crease.
//!
//! The surface is cut along its creases into smooth regions. A pocket is a set of small
//! regions that only one region (its host) separates from the rest of the mesh: removing the
//! host leaves them a component of their own, as a button's top and wall are once the panel
//! around it is gone, while a strip of a bevel leads on to further regions. Measured on the
//! shared PartNet-Mobility objects, the oven knobs, camera buttons and microwave dials welded
//! into their panels are pockets of their panel, and two bottles' caps pockets of their necks.

use uniphys_geometry::{DVec3, TriMesh};

use crate::candidates::UnionFind;
use crate::candidates::adjacency::WeldedEdges;

/// Most regions a pocket may hold (beyond it the search stops: a control is a few smooth
/// surfaces).
const POCKET_REGIONS_MAX: usize = 400;

/// The pockets of `mesh` whose area lies in `(min_m2, max_m2)` and whose host has at least
/// `host_ratio` times their area, each as its faces (sorted), in the order of their hosts
/// (largest first). `edges` are the mesh's welded edges; two faces sharing an edge are in
/// one smooth region when their normals are within `crease_rad` of each other (either
/// orientation: a model's winding is not trusted).
#[must_use]
pub fn crease_pockets(
    mesh: &TriMesh,
    edges: &WeldedEdges,
    face_area_m2: &[f64],
    crease_rad: f64,
    (min_m2, max_m2): (f64, f64),
    host_ratio: f64,
) -> Vec<Vec<usize>> {
    let (region, regions) = smooth_regions(mesh, edges, crease_rad);
    let mut region_m2 = vec![0.0f64; regions];
    for (f, &r) in region.iter().enumerate() {
        region_m2[r as usize] += face_area_m2[f];
    }
    let neighbours = region_neighbours(edges, &region, regions);
    let mut order: Vec<usize> = (0..regions).collect();
    order.sort_by(|&a, &b| region_m2[b].total_cmp(&region_m2[a]).then(a.cmp(&b)));
    let mut taken = vec![false; regions];
    let mut reached = Reached {
        host: vec![0; regions],
        current: 0,
        search: vec![0; regions],
        current_search: 0,
    };
    let mut pockets: Vec<Vec<usize>> = Vec::new();
    for &host in &order {
        if region_m2[host] < host_ratio * min_m2 {
            break;
        }
        reached.current += 1;
        for &start in &neighbours[host] {
            let start = start as usize;
            if taken[start] || region_m2[start] >= max_m2 {
                continue;
            }
            let found = behind((host, start), &neighbours, &region_m2, max_m2, &mut reached);
            let Some(members) = found else {
                continue;
            };
            let area_m2: f64 = members.iter().map(|&r| region_m2[r]).sum();
            if area_m2 <= min_m2 || region_m2[host] < host_ratio * area_m2 {
                continue;
            }
            for &r in &members {
                taken[r] = true;
            }
            pockets.push(members);
        }
    }
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); regions];
    for (f, &r) in region.iter().enumerate() {
        faces_of[r as usize].push(f);
    }
    pockets
        .into_iter()
        .map(|members| {
            let mut faces: Vec<usize> = members
                .iter()
                .flat_map(|&r| faces_of[r].iter().copied())
                .collect();
            faces.sort_unstable();
            faces
        })
        .collect()
}

/// What the searches for pockets have reached.
struct Reached {
    /// Per region, the host whose search last reached it (hosts numbered from 1).
    host: Vec<u32>,
    /// The host being searched behind.
    current: u32,
    /// Per region, the search that last reached it (searches numbered from 1).
    search: Vec<u32>,
    /// The search running.
    current_search: u32,
}

/// The regions reached from `start` without passing `host`, if they stay under `max_m2` and
/// [`POCKET_REGIONS_MAX`] regions (breadth first). Regions an earlier search behind the same
/// host reached without making a pocket of them lead on past the limits: reaching one fails.
fn behind(
    (host, start): (usize, usize),
    neighbours: &[Vec<u32>],
    region_m2: &[f64],
    max_m2: f64,
    reached: &mut Reached,
) -> Option<Vec<usize>> {
    if reached.host[start] == reached.current {
        return None;
    }
    reached.current_search += 1;
    let mut members = vec![start];
    reached.host[start] = reached.current;
    reached.search[start] = reached.current_search;
    let mut area_m2 = region_m2[start];
    let mut next = 0;
    while next < members.len() {
        let r = members[next];
        next += 1;
        for &n in &neighbours[r] {
            let n = n as usize;
            if n == host || reached.search[n] == reached.current_search {
                continue;
            }
            if reached.host[n] == reached.current {
                return None;
            }
            reached.host[n] = reached.current;
            reached.search[n] = reached.current_search;
            members.push(n);
            area_m2 += region_m2[n];
            if area_m2 >= max_m2 || members.len() > POCKET_REGIONS_MAX {
                return None;
            }
        }
    }
    Some(members)
}

/// Smooth regions: faces joined across edges of exactly two faces whose normals are within
/// `crease_rad` (either orientation; a face without area joins both sides). Returns the region
/// of every face and their count.
fn smooth_regions(mesh: &TriMesh, edges: &WeldedEdges, crease_rad: f64) -> (Vec<u32>, usize) {
    let normals: Vec<DVec3> = (0..mesh.triangle_count())
        .map(|f| mesh.face_normal(f))
        .collect();
    let smooth_cos = crease_rad.cos();
    let mut uf = UnionFind::new(mesh.triangle_count());
    for (f, &to) in edges.stands_for.iter().enumerate() {
        uf.union(u32::try_from(f).unwrap_or(u32::MAX), to);
    }
    for run in edges.runs() {
        if let [(_, _, f), (_, _, g)] = run {
            let (a, b) = (normals[*f as usize], normals[*g as usize]);
            // A face without a normal (no area) is no crease.
            if a == DVec3::ZERO || b == DVec3::ZERO || a.dot(b).abs() >= smooth_cos {
                uf.union(*f, *g);
            }
        }
    }
    let roots: Vec<u32> = (0..u32::try_from(mesh.triangle_count()).unwrap_or(u32::MAX))
        .map(|f| uf.find(f))
        .collect();
    crate::candidates::relabel_by_first_face(&roots)
}

/// For every region, the regions it meets along an edge (a crease, or an edge of three or
/// more faces), sorted.
fn region_neighbours(edges: &WeldedEdges, region: &[u32], regions: usize) -> Vec<Vec<u32>> {
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); regions];
    for run in edges.runs() {
        for (i, &(_, _, f)) in run.iter().enumerate() {
            for &(_, _, g) in &run[i + 1..] {
                let (a, b) = (region[f as usize], region[g as usize]);
                if a != b {
                    neighbours[a as usize].push(b);
                    neighbours[b as usize].push(a);
                }
            }
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    neighbours
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candidates::welded_vertex_ids;

    /// A flat square panel of `n` x `n` cells (side 1, z = 0) with, over the middle cell, a box
    /// bump of height `h` sharing the panel's vertices: the cell's four edges are where the bump's
    /// walls stand, its top at z = h.
    fn panel_with_bump(n: usize, h: f64) -> TriMesh {
        let mut positions = Vec::new();
        let id = |i: usize, j: usize| u32::try_from(i * (n + 1) + j).unwrap();
        for i in 0..=n {
            for j in 0..=n {
                positions.push(DVec3::new(i as f64 / n as f64, j as f64 / n as f64, 0.0));
            }
        }
        let mid = n / 2;
        let mut triangles = Vec::new();
        for i in 0..n {
            for j in 0..n {
                if (i, j) == (mid, mid) {
                    continue;
                }
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        // The bump: four wall quads from the cell's edges up to its top, and the top.
        let base = [
            id(mid, mid),
            id(mid + 1, mid),
            id(mid + 1, mid + 1),
            id(mid, mid + 1),
        ];
        let top: Vec<u32> = base
            .iter()
            .map(|&v| {
                let p = positions[v as usize];
                positions.push(DVec3::new(p.x, p.y, h));
                u32::try_from(positions.len() - 1).unwrap()
            })
            .collect();
        for k in 0..4 {
            let (a, b) = (base[k], base[(k + 1) % 4]);
            let (c, d) = (top[(k + 1) % 4], top[k]);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
        triangles.push([top[0], top[1], top[2]]);
        triangles.push([top[0], top[2], top[3]]);
        TriMesh {
            positions,
            triangles,
            ..TriMesh::default()
        }
    }

    fn pockets_of(mesh: &TriMesh) -> Vec<Vec<usize>> {
        let areas: Vec<f64> = (0..mesh.triangle_count())
            .map(|f| mesh.face_area(f))
            .collect();
        let total: f64 = areas.iter().sum();
        crease_pockets(
            mesh,
            &WeldedEdges::new(mesh, &welded_vertex_ids(mesh)),
            &areas,
            30f64.to_radians(),
            (1e-5 * total, 0.05 * total),
            2.0,
        )
    }

    #[test]
    fn a_bump_welded_into_its_panel_is_a_pocket_of_it() {
        let mesh = panel_with_bump(9, 0.05);
        let pockets = pockets_of(&mesh);
        assert_eq!(pockets.len(), 1, "{pockets:?}");
        // The bump's ten faces (four walls of two, a top of two), after the panel's 160.
        let bump: Vec<usize> = (160..170).collect();
        assert_eq!(pockets[0], bump);
    }

    #[test]
    fn a_flat_inlay_and_a_bump_too_large_for_a_control_are_no_pocket() {
        // Walls of no height (zero-area faces) are no crease: the top lies in the panel.
        assert!(pockets_of(&panel_with_bump(9, 0.0)).is_empty());
        // A ninth of the panel is more than the 5 % a control may hold.
        assert!(pockets_of(&panel_with_bump(3, 0.05)).is_empty());
    }
}
