//! Whether a slide's part sits between faces of its parent that face each other across it along
//! the axis, so that it pushes into its parent whichever way it goes: a lid seated in a pot's
//! rim slid sideways, a drawer slid across its slot into the carcass's side.
//!
//! Where a moving sample touches its parent, the parent's face there is turned to face the
//! sample (meshes of real objects are often open or drawn double-sided, so the winding says
//! nothing). A face facing along the axis stops the part going the other way. A slide is trapped
//! when both ways are stopped by faces at the two ends of the part: the faces facing back against
//! the slide lie further along the axis than those facing along it. A button pressed into its
//! face, a lid lifted off its rim and a drawer pulled out of its carcass are stopped one way only.
//! Faces facing both ways at one place (a part drawn slightly into its parent at rest, whose
//! samples lie on both sides of the face) hold nothing from the two ends.

use uniphys_geometry::{DVec3, projection_range};

use crate::held::Touch;

/// How a slide along an axis is held by its parent from the two ends along it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlideTrap {
    /// The weaker of the two ways the part is stopped: the sum of `(n . a)^2` over the touching
    /// samples whose parent face `n` faces along the axis `a`, or over those facing against it,
    /// whichever is smaller, over the touching samples (0: stopped at most one way).
    pub two_way_share: f64,
    /// How far the faces facing against the axis lie beyond those facing along it (each the
    /// mean position along the axis of its samples, weighted by `(n . a)^2`), a share of the
    /// moving parts' extent along the axis: about 1 when they hold the part at its two ends, near
    /// 0 when they are at one place.
    pub separation: f64,
}

/// A sample this close to the parent's face, as a share of the touch distance, lies on it: which
/// side it is on is unknown.
const ON_FACE_FRACTION: f64 = 1e-4;

/// The [`SlideTrap`] of a slide of the parts sampled at `moving` along unit `axis`, from where
/// they touch their parent within `touch_m` ([`touches`](crate::held::touches)); `None` with
/// fewer than 3 samples off a face.
pub(crate) fn slide_trap(
    touches: &[Touch],
    moving: &[DVec3],
    touch_m: f64,
    axis: DVec3,
) -> Option<SlideTrap> {
    let on_face_m = ON_FACE_FRACTION * touch_m;
    let mut touching = 0usize;
    // (weight, weighted position along the axis) of faces facing along the axis and against it.
    let (mut along, mut against) = ((0.0, 0.0), (0.0, 0.0));
    for touch in touches {
        let off = (touch.sample - touch.nearest).dot(touch.normal);
        if off.abs() <= on_face_m {
            continue;
        }
        touching += 1;
        let facing = touch.normal * off.signum();
        let c = facing.dot(axis);
        let w = c * c;
        let at = touch.sample.dot(axis);
        let side = if c > 0.0 { &mut along } else { &mut against };
        side.0 += w;
        side.1 += w * at;
    }
    if touching < 3 {
        return None;
    }
    let (lo, hi) = projection_range(moving, axis);
    let extent = (hi - lo).max(1e-12);
    let mean = |(w, wt): (f64, f64)| if w > 0.0 { wt / w } else { 0.0 };
    let separation = if along.0 > 0.0 && against.0 > 0.0 {
        (mean(against) - mean(along)) / extent
    } else {
        0.0
    };
    Some(SlideTrap {
        two_way_share: along.0.min(against.0) / touching as f64,
        separation,
    })
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::TriMesh;

    use super::*;
    use crate::held::touches;
    use crate::scene::Scene;

    /// A block standing 1 mm above a plate between two walls 2 mm from its ends along x.
    fn block_between_walls() -> Scene {
        let socket = TriMesh::merge([
            &TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.1)),
            &TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.1), DVec3::new(0.1, 1.0, 0.4)),
            &TriMesh::cuboid(DVec3::new(0.9, 0.0, 0.1), DVec3::new(1.0, 1.0, 0.4)),
        ]);
        let block = TriMesh::cuboid(DVec3::new(0.102, 0.2, 0.101), DVec3::new(0.898, 0.8, 0.3));
        Scene::of_convex_parts(&[socket, block], 3000)
    }

    #[test]
    fn a_block_between_two_walls_is_trapped_along_them_and_free_to_lift() {
        let s = block_between_walls();
        let moving = s.points_of(&[1]);
        let across =
            slide_trap(&touches(&s, 0, &moving, 0.02), &moving, 0.02, DVec3::X).expect("touching");
        assert!(across.two_way_share > 0.1, "{across:?}");
        assert!((across.separation - 1.0).abs() < 0.05, "{across:?}");
        // Lifted, it leaves the plate: stopped one way only.
        let lifted =
            slide_trap(&touches(&s, 0, &moving, 0.02), &moving, 0.02, DVec3::Z).expect("touching");
        assert_eq!(lifted.two_way_share, 0.0, "{lifted:?}");
    }

    #[test]
    fn a_block_against_one_wall_is_stopped_one_way_only() {
        let s = block_between_walls();
        // The half of the block by the left wall: the right wall is out of its reach.
        let moving: Vec<DVec3> = s
            .points_of(&[1])
            .into_iter()
            .filter(|p| p.x < 0.5)
            .collect();
        let trap =
            slide_trap(&touches(&s, 0, &moving, 0.02), &moving, 0.02, DVec3::X).expect("touching");
        assert_eq!(trap.two_way_share, 0.0, "{trap:?}");
    }

    #[test]
    fn a_block_sunk_into_a_plate_is_not_held_from_both_ends_of_its_lift() {
        // Its foot, 1 cm deep in the plate, has the plate's top face above it, and the block's
        // sides just above the plate have it below them: both at the same height.
        let plate = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.1));
        let block = TriMesh::cuboid(DVec3::new(0.4, 0.4, 0.09), DVec3::new(0.6, 0.6, 0.3));
        let s = Scene::of_convex_parts(&[plate, block], 3000);
        let moving = s.points_of(&[1]);
        let trap =
            slide_trap(&touches(&s, 0, &moving, 0.02), &moving, 0.02, DVec3::Z).expect("touching");
        assert!(trap.two_way_share > 0.0, "{trap:?}");
        assert!(trap.separation < 0.2, "{trap:?}");
    }
}
