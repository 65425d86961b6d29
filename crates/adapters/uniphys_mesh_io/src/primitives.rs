//! Closed, outward-wound tessellations of the URDF primitives, centred on the origin: box,
//! cylinder and capsule along Z, UV sphere.

use std::f64::consts::PI;

use uniphys_geometry::{DVec3, TriMesh};

/// Segments around the Z axis of cylinders, spheres and capsules.
pub(crate) const SEGMENTS: usize = 32;
/// Latitude bands of a sphere (half of them per capsule cap).
pub(crate) const STACKS: usize = 16;

/// An axis-aligned box with the given side lengths.
pub(crate) fn box_mesh(size: DVec3) -> TriMesh {
    TriMesh::cuboid(-0.5 * size, 0.5 * size)
}

/// A cylinder of the given radius and length along Z.
pub(crate) fn cylinder_mesh(radius: f64, length: f64) -> TriMesh {
    let h = 0.5 * length;
    lathe(&[(0.0, h), (radius, h), (radius, -h), (0.0, -h)])
}

/// A UV sphere of the given radius.
pub(crate) fn sphere_mesh(radius: f64) -> TriMesh {
    let profile: Vec<(f64, f64)> = (0..=STACKS)
        .map(|i| {
            let theta = PI * i as f64 / STACKS as f64;
            (radius * theta.sin(), radius * theta.cos())
        })
        .collect();
    lathe(&profile)
}

/// A capsule: a cylinder of the given radius and length along Z with hemispherical caps (total
/// height `length + 2 radius`, as in URDF and SDF).
pub(crate) fn capsule_mesh(radius: f64, length: f64) -> TriMesh {
    let h = 0.5 * length;
    let half = STACKS / 2;
    let mut profile = Vec::with_capacity(STACKS + 2);
    for i in 0..=half {
        let theta = PI * i as f64 / STACKS as f64;
        profile.push((radius * theta.sin(), h + radius * theta.cos()));
    }
    for i in half..=STACKS {
        let theta = PI * i as f64 / STACKS as f64;
        profile.push((radius * theta.sin(), -h + radius * theta.cos()));
    }
    lathe(&profile)
}

/// Revolves a profile of (radius, z) points about Z. The profile runs from the top pole
/// (radius 0) to the bottom pole (radius 0); poles become single vertices.
fn lathe(profile: &[(f64, f64)]) -> TriMesh {
    let rings = &profile[1..profile.len() - 1];
    let (top, bottom) = (profile[0].1, profile[profile.len() - 1].1);
    let mut positions = vec![DVec3::new(0.0, 0.0, top)];
    for &(r, z) in rings {
        for s in 0..SEGMENTS {
            let phi = 2.0 * PI * s as f64 / SEGMENTS as f64;
            positions.push(DVec3::new(r * phi.cos(), r * phi.sin(), z));
        }
    }
    positions.push(DVec3::new(0.0, 0.0, bottom));
    let south = u32::try_from(positions.len() - 1).unwrap_or(u32::MAX);
    let ring =
        |k: usize, s: usize| u32::try_from(1 + k * SEGMENTS + s % SEGMENTS).unwrap_or(u32::MAX);
    let mut triangles = Vec::new();
    for s in 0..SEGMENTS {
        triangles.push([0, ring(0, s), ring(0, s + 1)]);
    }
    for k in 0..rings.len().saturating_sub(1) {
        for s in 0..SEGMENTS {
            let (a, b, c, d) = (
                ring(k, s),
                ring(k, s + 1),
                ring(k + 1, s),
                ring(k + 1, s + 1),
            );
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    let last = rings.len() - 1;
    for s in 0..SEGMENTS {
        triangles.push([south, ring(last, s + 1), ring(last, s)]);
    }
    TriMesh {
        positions,
        triangles,
        ..TriMesh::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_volume(m: &TriMesh) -> f64 {
        (0..m.triangle_count())
            .map(|i| {
                let [a, b, c] = m.corners(i);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn box_is_closed_outward_with_exact_volume() {
        let m = box_mesh(DVec3::new(1.0, 2.0, 3.0));
        assert!(m.is_closed());
        assert!((signed_volume(&m) - 6.0).abs() < 1e-12);
    }

    #[test]
    fn cylinder_is_closed_outward_along_z_with_32_segments() {
        let m = cylinder_mesh(0.5, 2.0);
        assert!(m.is_closed());
        assert_eq!(m.triangle_count(), 4 * SEGMENTS);
        let b = m.bounds();
        assert!((b.min.z + 1.0).abs() < 1e-12 && (b.max.z - 1.0).abs() < 1e-12);
        let exact = PI * 0.25 * 2.0;
        let v = signed_volume(&m);
        assert!(
            v > 0.0 && (v - exact).abs() / exact < 0.01,
            "{v} vs {exact}"
        );
    }

    #[test]
    fn sphere_is_closed_outward_16_by_32() {
        let m = sphere_mesh(2.0);
        assert!(m.is_closed());
        assert_eq!(m.positions.len(), 2 + (STACKS - 1) * SEGMENTS);
        let exact = 4.0 / 3.0 * PI * 8.0;
        let v = signed_volume(&m);
        assert!(
            v > 0.0 && (v - exact).abs() / exact < 0.03,
            "{v} vs {exact}"
        );
    }

    #[test]
    fn capsule_is_closed_outward_with_caps_beyond_the_length() {
        let m = capsule_mesh(0.5, 2.0);
        assert!(m.is_closed());
        let b = m.bounds();
        assert!((b.max.z - 1.5).abs() < 1e-12 && (b.min.z + 1.5).abs() < 1e-12);
        let exact = PI * 0.25 * 2.0 + 4.0 / 3.0 * PI * 0.125;
        let v = signed_volume(&m);
        assert!(
            v > 0.0 && (v - exact).abs() / exact < 0.03,
            "{v} vs {exact}"
        );
    }
}
