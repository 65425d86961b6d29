//! Rays against a mesh: how far a ray goes before it meets a surface (parry's bounding volume
//! hierarchy over the triangles, in single precision about the mesh's centre).

use glam::DVec3;
use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};

use crate::TriMesh;

/// A mesh prepared for ray casts.
pub struct RayMesh {
    bvh: parry3d::shape::TriMesh,
    origin: DVec3,
}

impl std::fmt::Debug for RayMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RayMesh")
            .field("origin", &self.origin)
            .finish_non_exhaustive()
    }
}

impl RayMesh {
    /// `None` for a mesh without triangles.
    #[must_use]
    pub fn new(mesh: &TriMesh) -> Option<Self> {
        if mesh.triangles.is_empty() {
            return None;
        }
        let origin = mesh.bounds().center();
        let vertices: Vec<Vector> = mesh.positions.iter().map(|p| to_f32(*p - origin)).collect();
        let bvh = parry3d::shape::TriMesh::new(vertices, mesh.triangles.clone()).ok()?;
        Some(Self { bvh, origin })
    }

    /// How far the ray from `from` along unit `dir` goes before it meets a triangle (either
    /// face), metres; `None` when it meets none within `reach_m`.
    #[must_use]
    pub fn first_hit_m(&self, from: DVec3, dir: DVec3, reach_m: f64) -> Option<f64> {
        let ray = Ray::new(to_f32(from - self.origin), to_f32(dir));
        self.bvh
            .cast_local_ray(&ray, reach_m as f32, false)
            .map(f64::from)
    }
}

fn to_f32(p: DVec3) -> Vector {
    Vector::new(p.x as f32, p.y as f32, p.z as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_meets_the_nearest_face_of_a_box_and_misses_beside_it() {
        let rays = RayMesh::new(&TriMesh::cuboid(DVec3::ZERO, DVec3::ONE)).expect("mesh");
        let from = DVec3::new(0.5, 0.5, 3.0);
        let hit = rays.first_hit_m(from, -DVec3::Z, 10.0).expect("hit");
        assert!((hit - 2.0).abs() < 1e-5, "{hit}");
        assert_eq!(rays.first_hit_m(from, DVec3::Z, 10.0), None);
        assert_eq!(rays.first_hit_m(from, -DVec3::Z, 1.5), None);
        let inside = rays
            .first_hit_m(DVec3::splat(0.5), DVec3::X, 10.0)
            .expect("hit");
        assert!((inside - 0.5).abs() < 1e-5, "{inside}");
    }
}
