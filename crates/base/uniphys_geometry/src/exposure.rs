//! Whether a point of a surface can be reached from outside the object: a ray from it in some
//! direction leaves without meeting another surface. A surface right behind the point (the other
//! face of a sheet, a panel drawn flush against another) does not hide it; only surfaces farther
//! than a set gap do.

use glam::DVec3;

use crate::{RayMesh, TriMesh};

/// Rays against one mesh, for asking which of its points are exposed.
pub struct ExposureProbe {
    rays: RayMesh,
    reach_m: f64,
    skip_m: f64,
    directions: Vec<DVec3>,
}

impl std::fmt::Debug for ExposureProbe {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExposureProbe")
            .field("rays", &self.rays)
            .field("skip_m", &self.skip_m)
            .field("directions", &self.directions.len())
            .finish_non_exhaustive()
    }
}

impl ExposureProbe {
    /// A probe of `mesh` casting `directions` rays spread evenly over the sphere, which ignore
    /// surfaces nearer than `skip_rel` of the bounds diagonal. `None` for a mesh without extent
    /// or triangles.
    #[must_use]
    pub fn new(mesh: &TriMesh, directions: usize, skip_rel: f64) -> Option<Self> {
        let diagonal = mesh.bounds().diagonal();
        if !(diagonal.is_finite() && diagonal > 0.0) || mesh.triangles.is_empty() {
            return None;
        }
        Some(Self {
            rays: RayMesh::new(mesh)?,
            reach_m: 2.0 * diagonal,
            skip_m: skip_rel.max(0.0) * diagonal,
            directions: sphere_directions(directions.max(1)),
        })
    }

    /// Whether some ray from `point` leaves the object without meeting a surface beyond the gap
    /// the probe ignores.
    #[must_use]
    pub fn is_exposed(&self, point: DVec3) -> bool {
        self.directions.iter().any(|&dir| {
            self.rays
                .first_hit_m(point + dir * self.skip_m, dir, self.reach_m)
                .is_none()
        })
    }
}

/// `n` unit directions spread evenly over the sphere (a Fibonacci lattice), from near +z to near
/// -z.
#[must_use]
pub fn sphere_directions(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5.0f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn box_mesh(min: DVec3, max: DVec3) -> TriMesh {
        TriMesh::cuboid(min, max)
    }

    fn joined(meshes: &[TriMesh]) -> TriMesh {
        TriMesh::merge(meshes.iter())
    }

    #[test]
    fn a_point_inside_a_closed_box_is_hidden_and_one_outside_it_is_exposed() {
        let shell = box_mesh(DVec3::splat(-1.0), DVec3::splat(1.0));
        let probe = ExposureProbe::new(&shell, 24, 0.005).expect("probe");
        assert!(!probe.is_exposed(DVec3::ZERO));
        assert!(probe.is_exposed(DVec3::new(0.0, 0.0, 1.0)));
        assert!(probe.is_exposed(DVec3::new(3.0, 0.0, 0.0)));
    }

    #[test]
    fn a_surface_flush_behind_another_is_not_hidden_by_it_but_one_farther_away_is() {
        // A closed box with a plate just inside its top: the plate's points see out through the
        // top, whose gap is below the skip; a plate in the middle of the box does not.
        let shell = box_mesh(DVec3::splat(-1.0), DVec3::splat(1.0));
        let flush = box_mesh(DVec3::new(-0.5, -0.5, 0.99), DVec3::new(0.5, 0.5, 0.995));
        let probe = ExposureProbe::new(&joined(&[shell.clone(), flush]), 24, 0.005).expect("probe");
        assert!(probe.is_exposed(DVec3::new(0.0, 0.0, 0.995)));
        let middle = box_mesh(DVec3::new(-0.5, -0.5, 0.0), DVec3::new(0.5, 0.5, 0.005));
        let probe = ExposureProbe::new(&joined(&[shell, middle]), 24, 0.005).expect("probe");
        assert!(!probe.is_exposed(DVec3::new(0.0, 0.0, 0.005)));
    }

    #[test]
    fn the_directions_are_unit_and_cover_both_hemispheres() {
        let dirs = sphere_directions(24);
        assert_eq!(dirs.len(), 24);
        assert!(dirs.iter().all(|d| (d.length() - 1.0).abs() < 1e-12));
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            assert!(dirs.iter().any(|d| d.dot(axis) > 0.5));
            assert!(dirs.iter().any(|d| d.dot(axis) < -0.5));
        }
    }
}
