//! Convex colliders carved around a cavity: a carcass whose convex hull fills the slot its drawer
//! slides in leaves a gripper no room once the drawer is out. The space outside a box is the
//! union of the six half-spaces beyond its faces, so a convex hull minus the box is the union of
//! the hull clipped to each of them; each clipped piece is convex, and none enters the box.

use glam::DVec3;

use crate::{TriMesh, convex_hull};

/// A box with its own axes (a part's tight box: `uniphys_verify::PartBox::oriented`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientedBox {
    /// Centre, object frame.
    pub centre: DVec3,
    /// Unit, orthogonal axes.
    pub axes: [DVec3; 3],
    /// Half its extent along each axis.
    pub half_extents: DVec3,
}

impl OrientedBox {
    /// The box with each extent multiplied by `factor` about its centre.
    #[must_use]
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            half_extents: self.half_extents * factor.max(0.0),
            ..*self
        }
    }

    /// Its six faces as (outward normal, offset): a point `p` is beyond the face when
    /// `normal . p > offset`.
    fn faces(&self) -> [(DVec3, f64); 6] {
        let h = self.half_extents.to_array();
        let face = |k: usize, sign: f64| {
            let n = self.axes[k] * sign;
            (n, n.dot(self.centre) + h[k])
        };
        [
            face(0, 1.0),
            face(0, -1.0),
            face(1, 1.0),
            face(1, -1.0),
            face(2, 1.0),
            face(2, -1.0),
        ]
    }
}

/// `hull` (convex, closed) without what lies inside `cavity`: the hull itself when they do not
/// overlap, else the convex pieces of it beyond each face of the box (empty when the hull lies
/// inside the box). Pieces thinner than `min_thickness` beyond their face are dropped.
#[must_use]
pub fn carve_out(hull: &TriMesh, cavity: &OrientedBox, min_thickness: f64) -> Vec<TriMesh> {
    let faces = cavity.faces();
    let beyond = |(n, d): (DVec3, f64), p: &DVec3| n.dot(*p) - d;
    // Separated: all of the hull beyond one face.
    if faces
        .iter()
        .any(|&f| hull.positions.iter().all(|p| beyond(f, p) >= 0.0))
    {
        return vec![hull.clone()];
    }
    let edges: Vec<(usize, usize)> = hull
        .triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b) as usize, a.max(b) as usize))
        .collect();
    let mut pieces = Vec::new();
    for face in faces {
        let depth = hull
            .positions
            .iter()
            .map(|p| beyond(face, p))
            .fold(f64::NEG_INFINITY, f64::max);
        if depth < min_thickness {
            continue;
        }
        let mut points: Vec<DVec3> = hull
            .positions
            .iter()
            .filter(|p| beyond(face, p) >= 0.0)
            .copied()
            .collect();
        for &(a, b) in &edges {
            let (pa, pb) = (hull.positions[a], hull.positions[b]);
            let (da, db) = (beyond(face, &pa), beyond(face, &pb));
            if (da < 0.0) != (db < 0.0) {
                points.push(pa + (pb - pa) * (da / (da - db)));
            }
        }
        if let Ok(piece) = convex_hull(&points) {
            pieces.push(piece);
        }
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cavity() -> OrientedBox {
        OrientedBox {
            centre: DVec3::new(0.0, 0.0, 0.5),
            axes: [DVec3::X, DVec3::Y, DVec3::Z],
            half_extents: DVec3::new(0.3, 0.3, 0.2),
        }
    }

    fn inside_cavity(p: DVec3) -> bool {
        let c = cavity();
        (p - c.centre)
            .abs()
            .cmplt(c.half_extents - DVec3::splat(1e-9))
            .all()
    }

    #[test]
    fn a_carcass_block_loses_its_drawer_slot_and_keeps_the_rest() {
        let block = TriMesh::cuboid(DVec3::new(-0.4, -0.4, 0.0), DVec3::new(0.4, 0.4, 1.0));
        let pieces = carve_out(&block, &cavity(), 1e-3);
        assert_eq!(pieces.len(), 6);
        for piece in &pieces {
            assert!(piece.positions.iter().all(|p| !inside_cavity(*p)));
        }
        // The pieces still reach every corner of the block and the slot's middle is empty.
        let corners = TriMesh::merge(&pieces).bounds();
        assert!((corners.min - block.bounds().min).length() < 1e-9);
        assert!((corners.max - block.bounds().max).length() < 1e-9);
    }

    #[test]
    fn a_hull_clear_of_the_cavity_is_kept_and_one_inside_it_goes() {
        let beside = TriMesh::cuboid(DVec3::new(0.5, -0.4, 0.0), DVec3::new(0.6, 0.4, 1.0));
        assert_eq!(carve_out(&beside, &cavity(), 1e-3), vec![beside.clone()]);
        let rail = TriMesh::cuboid(DVec3::new(-0.1, -0.1, 0.4), DVec3::new(0.1, 0.1, 0.45));
        assert!(carve_out(&rail, &cavity(), 1e-3).is_empty());
    }
}
