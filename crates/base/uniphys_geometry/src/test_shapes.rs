//! Closed and open test meshes with hand-known geometry (test builds only).

use std::collections::HashMap;

use glam::DVec3;

use crate::TriMesh;
pub(crate) use crate::mesh::tests::unit_box;

/// Icosahedron refined `subdivisions` times and projected onto the sphere of `radius` about
/// the origin; outward winding, 20 * 4^subdivisions triangles.
pub(crate) fn icosphere(radius: f64, subdivisions: u32) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<DVec3>| {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                u32::try_from(positions.len() - 1).unwrap()
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for &[a, b, c] in &triangles {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let positions = positions.into_iter().map(|p| p * radius).collect();
    TriMesh::new(positions, triangles).unwrap()
}

/// The L-shaped outline (0,0) (2,0) (2,1) (1,1) (1,2) (0,2) extruded from z = 0 to z = 1:
/// a closed, non-convex solid of volume 3 whose convex hull has volume 3.5.
pub(crate) fn l_prism() -> TriMesh {
    let outline = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let mut positions: Vec<DVec3> = outline
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 0.0))
        .collect();
    positions.extend(outline.iter().map(|&(x, y)| DVec3::new(x, y, 1.0)));
    let cap = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]];
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    triangles.extend(cap.iter().map(|&[a, b, c]| [a + 6, b + 6, c + 6]));
    triangles.extend(cap.iter().map(|&[a, b, c]| [a, c, b]));
    for i in 0..6u32 {
        let j = (i + 1) % 6;
        triangles.push([i, j, j + 6]);
        triangles.push([i, j + 6, i + 6]);
    }
    TriMesh::new(positions, triangles).unwrap()
}

/// The unit cube without its +z face: five faces, open at the top.
pub(crate) fn open_box() -> TriMesh {
    let closed = unit_box(DVec3::ZERO, DVec3::ONE);
    let keep: Vec<usize> = (0..closed.triangle_count())
        .filter(|&i| closed.face_normal(i).z < 0.5)
        .collect();
    closed.submesh(&keep)
}

/// Two disjoint unit cubes, [0,1]^3 and [3,4]x[0,1]x[0,1], in one mesh.
pub(crate) fn two_boxes() -> TriMesh {
    TriMesh::merge([
        &unit_box(DVec3::ZERO, DVec3::ONE),
        &unit_box(DVec3::new(3.0, 0.0, 0.0), DVec3::new(4.0, 1.0, 1.0)),
    ])
}

#[test]
fn shapes_have_their_documented_volumes() {
    use crate::MassProperties;
    let volume = |m: &TriMesh| MassProperties::from_closed_mesh(m).unwrap().volume_m3;
    assert!((volume(&l_prism()) - 3.0).abs() < 1e-12);
    assert!((volume(&two_boxes()) - 2.0).abs() < 1e-12);
    // A fine icosphere is close to the ball volume 4/3 pi r^3 (from below).
    let v = volume(&icosphere(1.0, 4));
    assert!(v < 4.0 / 3.0 * std::f64::consts::PI && v > 4.1, "{v}");
    assert_eq!(open_box().triangle_count(), 10);
    assert!(!open_box().is_closed());
}
