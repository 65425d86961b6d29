//! Small meshes shared by the perception tests.

use uniphys_geometry::{DVec3, TriMesh};

/// Axis-aligned boxes `(lo, hi)` merged into one mesh, 12 faces each in order.
pub(crate) fn boxes(boxes: &[(DVec3, DVec3)]) -> TriMesh {
    let meshes: Vec<TriMesh> = boxes
        .iter()
        .map(|&(lo, hi)| TriMesh::cuboid(lo, hi))
        .collect();
    TriMesh::merge(&meshes)
}

/// Faces of one cuboid made by [`TriMesh::cuboid`].
pub(crate) const CUBOID_FACES: usize = 12;

/// A 1 x 1 x 0.6 m box (faces 0..12) with a thinner, inset 0.7 x 0.7 x 0.1 m lid on top (faces
/// 12..24).
pub(crate) fn box_with_inset_lid() -> TriMesh {
    let body = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.6));
    let lid = TriMesh::cuboid(DVec3::new(0.15, 0.15, 0.6), DVec3::new(0.85, 0.85, 0.7));
    TriMesh::merge([&body, &lid])
}

/// A 1 x 1 x 0.6 m box (faces 0..12) with a lid of the same footprint, 0.15 m thick, flush with
/// its sides (faces 12..24).
pub(crate) fn box_with_flush_lid() -> TriMesh {
    let body = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.6));
    let lid = TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.6), DVec3::new(1.0, 1.0, 0.75));
    TriMesh::merge([&body, &lid])
}

/// One closed L-shaped solid: the profile (x, z) = (0,0) (1,0) (1,0.3) (0.3,0.3) (0.3,1) (0,1)
/// extruded along y from 0 to 0.8 m. Its inner corner is a concave crease.
pub(crate) fn l_shaped_solid() -> TriMesh {
    let profile = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 0.3),
        (0.3, 0.3),
        (0.3, 1.0),
        (0.0, 1.0),
    ];
    let mut positions: Vec<DVec3> = profile
        .iter()
        .map(|&(x, z)| DVec3::new(x, 0.0, z))
        .collect();
    positions.extend(profile.iter().map(|&(x, z)| DVec3::new(x, 0.8, z)));
    // Caps: a fan from the reflex vertex 3 (the profile is star-shaped from it).
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (a, b) in [(4, 5), (5, 0), (0, 1), (1, 2)] {
        triangles.push([3, b, a]);
        triangles.push([9, a + 6, b + 6]);
    }
    for i in 0..6u32 {
        let j = (i + 1) % 6;
        triangles.push([i, j, j + 6]);
        triangles.push([i, j + 6, i + 6]);
    }
    TriMesh {
        positions,
        triangles,
        ..TriMesh::default()
    }
}

/// The box `min..max` with every side split into `n x n` quads (12 n^2 triangles), sides in the
/// order -z, +z, -y, +y, -x, +x.
pub(crate) fn fine_cuboid(min: DVec3, max: DVec3, n: usize) -> TriMesh {
    let size = max - min;
    let sides = [
        (min, DVec3::Y * size.y, DVec3::X * size.x),
        (
            DVec3::new(min.x, min.y, max.z),
            DVec3::X * size.x,
            DVec3::Y * size.y,
        ),
        (min, DVec3::X * size.x, DVec3::Z * size.z),
        (
            DVec3::new(min.x, max.y, min.z),
            DVec3::Z * size.z,
            DVec3::X * size.x,
        ),
        (min, DVec3::Z * size.z, DVec3::Y * size.y),
        (
            DVec3::new(max.x, min.y, min.z),
            DVec3::Y * size.y,
            DVec3::Z * size.z,
        ),
    ];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let step = 1.0 / n as f64;
    for (corner, u, v) in sides {
        let base = positions.len();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(corner + u * (i as f64 * step) + v * (j as f64 * step));
            }
        }
        let at = |i: usize, j: usize| u32::try_from(base + j * (n + 1) + i).unwrap_or(u32::MAX);
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    TriMesh {
        positions,
        triangles,
        ..TriMesh::default()
    }
}

/// A 1 x 0.8 x 0.9 m body (faces 0..12), a drawer front 0.05 m proud of its -y side (faces
/// 12..24) and a bar handle on the drawer front (faces 24..36).
pub(crate) fn body_drawer_handle() -> TriMesh {
    let body = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.9));
    let drawer = TriMesh::cuboid(DVec3::new(0.15, -0.05, 0.15), DVec3::new(0.85, 0.0, 0.75));
    let handle = TriMesh::cuboid(DVec3::new(0.3, -0.12, 0.6), DVec3::new(0.7, -0.05, 0.66));
    TriMesh::merge([&body, &drawer, &handle])
}
