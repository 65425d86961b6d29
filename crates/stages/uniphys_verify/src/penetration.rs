//! Interpenetration of convex colliders, measured with parry's contact queries (GJK/EPA).

use parry3d::bounding_volume::{Aabb, BoundingVolume};
use parry3d::math::{Pose, Vector};
use parry3d::shape::ConvexPolyhedron;
use uniphys_geometry::{DVec3, TriMesh};

use crate::motion::JointMotion;

/// One convex collider of a part, in the object frame relative to `origin` (f32 precision is
/// kept by working near the object's centre).
pub(crate) struct Hull {
    pub(crate) part: usize,
    pub(crate) shape: ConvexPolyhedron,
    /// Bounds at rest, in the shifted frame.
    rest_aabb: Aabb,
    /// Bounding sphere in the object frame: centre and radius, metres.
    centre_m: DVec3,
    radius_m: f64,
}

/// Convex colliders of all parts, shifted by a common origin.
pub(crate) struct Colliders {
    pub(crate) origin: DVec3,
    pub(crate) hulls: Vec<Hull>,
}

impl Colliders {
    /// The hulls of each part (`colliders[part]`), relative to `origin`. Hulls parry cannot
    /// build (flat or degenerate) are skipped.
    pub(crate) fn new(colliders: &[Vec<TriMesh>], origin: DVec3) -> Self {
        let mut hulls = Vec::new();
        for (part, meshes) in colliders.iter().enumerate() {
            for mesh in meshes {
                let points: Vec<Vector> =
                    mesh.positions.iter().map(|p| to_f32(*p - origin)).collect();
                if let Some(shape) = ConvexPolyhedron::from_convex_hull(&points) {
                    let centre_m =
                        mesh.positions.iter().sum::<DVec3>() / mesh.positions.len().max(1) as f64;
                    let radius_m = mesh
                        .positions
                        .iter()
                        .map(|p| p.distance(centre_m))
                        .fold(0.0, f64::max);
                    hulls.push(Hull {
                        part,
                        rest_aabb: shape.aabb(&Pose::IDENTITY),
                        shape,
                        centre_m,
                        radius_m,
                    });
                }
            }
        }
        Self { origin, hulls }
    }

    /// Hull indices of the given parts.
    pub(crate) fn of_parts(&self, parts: &[usize]) -> Vec<usize> {
        (0..self.hulls.len())
            .filter(|&h| parts.contains(&self.hulls[h].part))
            .collect()
    }

    /// Whether moving hull `a` can come near still hull `b` while the joint moves from `lower`
    /// to `upper` (a broad phase: pairs that cannot meet are never queried). A turning hull
    /// stays inside the sphere about the foot of its centre on the axis that contains it; a
    /// sliding one inside the capsule its sphere sweeps.
    pub(crate) fn may_meet(
        &self,
        a: usize,
        b: usize,
        motion: &JointMotion,
        lower: f64,
        upper: f64,
    ) -> bool {
        let (ha, hb) = (&self.hulls[a], &self.hulls[b]);
        motion.may_reach(
            ha.centre_m,
            ha.radius_m,
            (lower, upper),
            hb.centre_m,
            hb.radius_m,
        )
    }

    /// The hulls `moving` at coordinate `q` of `motion`, in the shifted frame.
    pub(crate) fn posed(&self, motion: &JointMotion, q: f64, moving: &[usize]) -> Posed {
        // x' = R x + t in the object frame; with x = y + o: y' = R y + (R o + t - o).
        let rotation = motion.rotation(q);
        let translation = rotation * self.origin + motion.translation_m(q) - self.origin;
        let r = rotation.as_quat();
        let pose = Pose::from_parts(to_f32(translation), r.normalize());
        let mut aabbs = vec![None; self.hulls.len()];
        for &h in moving {
            aabbs[h] = Some(self.hulls[h].shape.aabb(&pose));
        }
        Posed { pose, aabbs }
    }

    /// Penetration depth (metres, 0 when separate or touching) of moving hull `a` at `posed`
    /// into static hull `b` at rest.
    pub(crate) fn depth_m(&self, a: usize, posed: &Posed, b: usize) -> f64 {
        let (ha, hb) = (&self.hulls[a].shape, &self.hulls[b]);
        let aabb_a = posed.aabbs[a].unwrap_or_else(|| ha.aabb(&posed.pose));
        if !aabb_a.intersects(&hb.rest_aabb) {
            return 0.0;
        }
        match parry3d::query::contact(&posed.pose, ha, &Pose::IDENTITY, &hb.shape, 0.0) {
            Ok(Some(contact)) if contact.dist < 0.0 => f64::from(-contact.dist),
            _ => 0.0,
        }
    }
}

/// Moving hulls at one coordinate of their joint: the pose, and the bounds there of each hull
/// it was made for, found once for all the pairs a hull is in.
pub(crate) struct Posed {
    pose: Pose,
    /// Bounds at the pose, by hull index (`None` for hulls that were not posed).
    aabbs: Vec<Option<Aabb>>,
}

/// A point in parry's `f32` vectors.
pub(crate) fn to_f32(p: DVec3) -> Vector {
    Vector::new(p.x as f32, p.y as f32, p.z as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use uniphys_types::JointKind;

    #[test]
    fn overlapping_boxes_report_their_overlap_depth() {
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::new(0.9, 0.0, 0.0), DVec3::new(2.0, 1.0, 1.0));
        let colliders = Colliders::new(&[vec![a], vec![b]], DVec3::splat(0.5));
        let still = JointMotion {
            kind: JointKind::Prismatic,
            axis_in_object: DVec3::X,
            pivot_in_object_m: DVec3::ZERO,
        };
        let d = colliders.depth_m(0, &colliders.posed(&still, 0.0, &[0]), 1);
        assert!((d - 0.1).abs() < 1e-5, "{d}");
        // Moved 0.3 m further along +x the overlap is 0.4 m; moved back 0.2 m they are apart.
        let d = colliders.depth_m(0, &colliders.posed(&still, 0.3, &[0]), 1);
        assert!((d - 0.4).abs() < 1e-5, "{d}");
        assert_eq!(
            colliders.depth_m(0, &colliders.posed(&still, -0.2, &[0]), 1),
            0.0
        );
    }

    #[test]
    fn rotation_about_a_pivot_matches_the_point_transform() {
        let a = TriMesh::cuboid(DVec3::new(1.0, -0.1, -0.1), DVec3::new(2.0, 0.1, 0.1));
        // A quarter turn of the bar about +z through the origin puts it along +y from 1 to 2,
        // through the wall at y in [1.4, 1.6].
        let wall = TriMesh::cuboid(DVec3::new(-0.5, 1.4, -0.5), DVec3::new(0.5, 1.6, 0.5));
        let colliders = Colliders::new(&[vec![a], vec![wall]], DVec3::new(0.3, 0.2, 0.0));
        let hinge = JointMotion {
            kind: JointKind::Revolute,
            axis_in_object: DVec3::Z,
            pivot_in_object_m: DVec3::ZERO,
        };
        assert_eq!(
            colliders.depth_m(0, &colliders.posed(&hinge, 0.0, &[0]), 1),
            0.0
        );
        let d = colliders.depth_m(
            0,
            &colliders.posed(&hinge, std::f64::consts::FRAC_PI_2, &[0]),
            1,
        );
        // Every separating translation is 0.6 m long (along x, y or z).
        assert!((d - 0.6).abs() < 1e-4, "{d}");
    }
}
