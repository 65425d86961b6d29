use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::{GeometryError, GeometryResult, TriMesh};

/// The convex hull of `points` as a closed mesh with outward winding.
///
/// Computed by parry3d in `f32` on the points taken relative to their centroid; the hull's
/// vertices are then mapped back to the original `f64` input points, so no precision is lost
/// in the output positions.
///
/// Errors: a non-finite point is [`GeometryError::NonFiniteVertex`]; fewer than 4 points, or
/// (nearly) coplanar points, are [`GeometryError::NotEnoughInput`]; a failure inside parry3d is
/// [`GeometryError::ConvexHull`].
pub fn convex_hull(points: &[DVec3]) -> GeometryResult<TriMesh> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(GeometryError::NonFiniteVertex { index });
    }
    if points.len() < 4 {
        return Err(GeometryError::NotEnoughInput(format!(
            "a convex hull needs 4 points, got {}",
            points.len()
        )));
    }
    let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
    let local: Vec<Vec3> = points.iter().map(|p| (*p - centroid).as_vec3()).collect();
    let (vertices, triangles) = parry3d::transformation::try_convex_hull(&local)
        .map_err(|e| GeometryError::ConvexHull(e.to_string()))?;
    let key = |v: &Vec3| v.to_array().map(f32::to_bits);
    let mut original: HashMap<[u32; 3], usize> = HashMap::with_capacity(local.len());
    for (i, v) in local.iter().enumerate() {
        original.entry(key(v)).or_insert(i);
    }
    let positions = vertices
        .iter()
        .map(|v| {
            original
                .get(&key(v))
                .map_or(centroid + v.as_dvec3(), |&i| points[i])
        })
        .collect();
    let mut mesh = TriMesh::new(positions, triangles)?;
    let signed_volume: f64 = (0..mesh.triangle_count())
        .map(|i| {
            let [a, b, c] = mesh.corners(i).map(|p| p - centroid);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    if signed_volume < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    let diagonal = mesh.bounds().diagonal();
    if !mesh.is_closed() || signed_volume.abs() <= 1e-9 * diagonal.powi(3) {
        return Err(GeometryError::NotEnoughInput(
            "the points are (nearly) coplanar, so their hull has no volume".to_owned(),
        ));
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MassProperties;
    use crate::test_shapes::{icosphere, l_prism, unit_box};

    #[test]
    fn hull_of_a_box_with_inner_points_is_the_box() {
        let mut points = unit_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)).positions;
        points.extend([DVec3::new(0.5, 1.0, 1.5), DVec3::new(0.2, 0.3, 0.4)]);
        let hull = convex_hull(&points).unwrap();
        let m = MassProperties::from_closed_mesh(&hull).unwrap();
        assert!((m.volume_m3 - 6.0).abs() < 1e-9);
        assert!((m.com - DVec3::new(0.5, 1.0, 1.5)).length() < 1e-9);
        assert!(hull.positions.iter().all(|p| points[..8].contains(p)));
    }

    #[test]
    fn hull_of_the_l_prism_fills_the_notch() {
        // The L outline's hull cuts the notch corner diagonally: 4 - 1/2 = 3.5 m^2, times 1 m.
        let hull = convex_hull(&l_prism().positions).unwrap();
        let m = MassProperties::from_closed_mesh(&hull).unwrap();
        assert!((m.volume_m3 - 3.5).abs() < 1e-9, "{}", m.volume_m3);
    }

    #[test]
    fn far_from_origin_points_keep_their_precision() {
        let offset = DVec3::new(1e6, -2e6, 3e5);
        let sphere = icosphere(0.01, 1);
        let points: Vec<DVec3> = sphere.positions.iter().map(|p| *p + offset).collect();
        let hull = convex_hull(&points).unwrap();
        // All 42 vertices are extreme, and come back bit-exact.
        assert_eq!(hull.positions.len(), 42);
        assert!(hull.positions.iter().all(|p| points.contains(p)));
        assert!(MassProperties::from_closed_mesh(&hull).is_some());
    }

    #[test]
    fn too_few_coplanar_or_nan_points_are_rejected() {
        assert!(matches!(
            convex_hull(&[DVec3::ZERO, DVec3::X, DVec3::Y]),
            Err(GeometryError::NotEnoughInput(_))
        ));
        let square = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        assert!(convex_hull(&square).is_err());
        assert_eq!(
            convex_hull(&[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NAN]),
            Err(GeometryError::NonFiniteVertex { index: 3 })
        );
    }
}
