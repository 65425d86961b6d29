//! Axis and pivot hypotheses for sliding and hinged parts from their bounding boxes.
//!
//! This is the foundation's geometric heuristic; the simulation-driven grounder replaces it.

use uniphys_geometry::{Aabb, DVec3};

/// An axis, a point on it, and the motion range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AxisHypothesis {
    pub axis: DVec3,
    pub pivot: DVec3,
    pub lower: f64,
    pub upper: f64,
}

const HORIZONTAL: [DVec3; 4] = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y];

/// Support of a box along a signed unit axis: the largest `p . d` over the box.
fn support(b: &Aabb, d: DVec3) -> f64 {
    b.max.dot(d.max(DVec3::ZERO)) + b.min.dot(d.min(DVec3::ZERO))
}

/// A sliding part moves out along the horizontal direction in which its parent encloses it the
/// least (a drawer front is flush with or proud of the carcass; its sides are inside it).
/// The range is 80 % of the part's depth along that direction.
pub(crate) fn slide(child: &Aabb, parent: &Aabb) -> AxisHypothesis {
    let margin = |d: DVec3| support(parent, d) - support(child, d);
    let axis = HORIZONTAL
        .into_iter()
        .min_by(|a, b| margin(*a).total_cmp(&margin(*b)))
        .unwrap_or(DVec3::NEG_Y);
    let depth = child.extents().dot(axis.abs());
    AxisHypothesis {
        axis,
        pivot: child.center(),
        lower: 0.0,
        upper: 0.8 * depth,
    }
}

/// A hinged part is treated as a slab: its hinge runs along one edge of the slab's face.
/// The edge is the one farthest from `away_from` (a handle on the part) when given, otherwise
/// the one closest to `contact` (the centroid of the contact with the parent). Among edges within
/// 5 % of the part's size of the best, the longer edge wins. The axis sign makes a positive
/// angle move the part's centre away from the parent's centre; the range is 0 to 90 degrees.
pub(crate) fn hinge(
    child: &Aabb,
    parent_center: DVec3,
    contact: Option<DVec3>,
    away_from: Option<DVec3>,
) -> AxisHypothesis {
    let ext = child.extents();
    let c = child.center();
    let thin = (0..3)
        .min_by(|&a, &b| ext[a].total_cmp(&ext[b]))
        .unwrap_or(2);
    let in_plane: Vec<usize> = (0..3).filter(|&k| k != thin).collect();
    // Candidate edges: axis along in_plane[a], line at min or max of the other in-plane axis.
    let mut candidates = Vec::new();
    for (ai, &along) in in_plane.iter().enumerate() {
        let across = in_plane[1 - ai];
        for side in [child.min[across], child.max[across]] {
            let mut pivot = c;
            pivot[across] = side;
            let mut axis = DVec3::ZERO;
            axis[along] = 1.0;
            candidates.push((axis, pivot, ext[along]));
        }
    }
    let line_distance =
        |p: DVec3, axis: DVec3, q: DVec3| (q - p).reject_from_normalized(axis).length();
    let score = |&(axis, pivot, _): &(DVec3, DVec3, f64)| match (away_from, contact) {
        (Some(h), _) => -line_distance(pivot, axis, h),
        (None, Some(q)) => line_distance(pivot, axis, q),
        (None, None) => 0.0,
    };
    let best_score = candidates.iter().map(score).fold(f64::INFINITY, f64::min);
    let tolerance = 0.05 * ext.length();
    let (axis, pivot, _) = candidates
        .iter()
        .filter(|cand| score(cand) <= best_score + tolerance)
        .copied()
        .max_by(|a, b| a.2.total_cmp(&b.2).then(a.1.y.total_cmp(&b.1.y)))
        .unwrap_or((DVec3::Z, c, 0.0));
    // Positive rotation moves the centre away from the parent.
    let velocity = axis.cross(c - pivot);
    let outward = c - parent_center;
    let axis = if velocity.dot(outward) < 0.0 {
        -axis
    } else {
        axis
    };
    AxisHypothesis {
        axis,
        pivot,
        lower: 0.0,
        upper: std::f64::consts::FRAC_PI_2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn aabb(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb {
            min: DVec3::from_array(min),
            max: DVec3::from_array(max),
        }
    }

    #[test]
    fn drawer_slides_out_of_the_open_front() {
        let carcass = aabb([-0.3, -0.2, 0.0], [0.3, 0.2, 0.8]);
        let drawer = aabb([-0.28, -0.21, 0.5], [0.28, 0.18, 0.7]);
        let h = slide(&drawer, &carcass);
        assert_eq!(h.axis, DVec3::NEG_Y);
        assert!((h.upper - 0.8 * 0.39).abs() < 1e-9);
    }

    #[test]
    fn door_hinges_on_the_edge_opposite_its_handle_and_opens_outward() {
        // A door slab at the front (-y) of a carcass, handle near +x.
        let door = aabb([-0.3, -0.22, 0.0], [0.3, -0.2, 0.4]);
        let handle = DVec3::new(0.25, -0.24, 0.2);
        let h = hinge(&door, DVec3::new(0.0, 0.0, 0.4), None, Some(handle));
        assert!((h.axis.abs() - DVec3::Z).length() < 1e-12, "{:?}", h.axis);
        assert!((h.pivot.x + 0.3).abs() < 1e-12);
        // A small positive rotation moves the door centre toward -y (away from the carcass).
        let v = h.axis.cross(door.center() - h.pivot);
        assert!(v.y < 0.0);
    }

    #[test]
    fn lid_hinges_at_the_contact_edge_and_opens_upward() {
        let lid = aabb([-0.15, -0.1, 0.15], [0.15, 0.1, 0.16]);
        let contact = DVec3::new(0.0, 0.1, 0.15);
        let h = hinge(&lid, DVec3::new(0.0, 0.0, 0.075), Some(contact), None);
        assert!((h.pivot.y - 0.1).abs() < 1e-12);
        assert!((h.axis.abs() - DVec3::X).length() < 1e-12);
        let v = h.axis.cross(lid.center() - h.pivot);
        assert!(v.z > 0.0);
    }
}
