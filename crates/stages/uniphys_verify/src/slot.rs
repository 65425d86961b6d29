//! Whether a part sits in a slot along an axis: its parent walls it in on the sides across the
//! axis (a drawer between a carcass's sides, bottom and top), measured by rays cast from inside
//! the moving part towards each side. A long slide must run in one; a hinge must not turn its
//! part about one's axis (what sits in a slot slides along it).

use uniphys_geometry::{Aabb, DVec3, box_axes, projection_range};

use crate::candidates::across_axis;
use crate::scene::Scene;

/// Fractions of the moving part's extent along the slide where rays start (its middle, away
/// from a drawer's front panel and its back).
const ALONG_FRACTIONS: [f64; 5] = [0.2, 0.35, 0.5, 0.65, 0.8];
/// Fractions of the part's extent along the other direction across the slide where rays start.
const ACROSS_FRACTIONS: [f64; 3] = [0.25, 0.5, 0.75];
/// How far beyond the part's own extent a wall may stand, as a fraction of the part's diagonal.
const WALL_REACH_FRACTION: f64 = 0.25;
/// A side is walled when at least this share of its rays meets the parent.
const WALLED_RAY_SHARE: f64 = 0.5;

/// How many of the four sides across `axis` (both ways along the two directions across it) the
/// parts `walls` (the parent, or every still part) wall in the moving part (its samples
/// `moving`): from points inside the part's box, spread along the slide and across it, rays go
/// towards each side as far as the part reaches plus a quarter of its diagonal; a side whose
/// rays mostly meet a wall's surface is walled.
/// Real drawers of the shared objects: 2 to 4 (one hanging under a table top alone: 1); a door,
/// lid or screen pushed along its own face: usually 0 or 1.
pub(crate) fn walled_sides(scene: &Scene, walls: &[usize], moving: &[DVec3], axis: DVec3) -> usize {
    let axis = axis.normalize_or_zero();
    if moving.is_empty() || axis == DVec3::ZERO {
        return 0;
    }
    let Some((u, v)) = across_axis(axis, box_axes(moving)) else {
        return 0;
    };
    let reach_m = WALL_REACH_FRACTION * Aabb::from_points(moving).diagonal();
    let along = projection_range(moving, axis);
    let ranges = [projection_range(moving, u), projection_range(moving, v)];
    let directions = [u, v];
    let at = |(lo, hi): (f64, f64), f: f64| lo + f * (hi - lo);
    let mut walled = 0;
    for dim in 0..2 {
        let (side, other) = (directions[dim], directions[1 - dim]);
        let (lo, hi) = ranges[dim];
        let middle = 0.5 * (lo + hi);
        for sign in [1.0, -1.0] {
            let length = 0.5 * (hi - lo) + reach_m;
            let mut hits = 0;
            let mut rays = 0;
            for fa in ALONG_FRACTIONS {
                for fo in ACROSS_FRACTIONS {
                    let from =
                        axis * at(along, fa) + other * at(ranges[1 - dim], fo) + side * middle;
                    let to = from + side * (sign * length);
                    rays += 1;
                    if walls
                        .iter()
                        .any(|&w| scene.surfaces.crossing(w, from, to).is_some())
                    {
                        hits += 1;
                    }
                }
            }
            if hits as f64 >= WALLED_RAY_SHARE * rays as f64 {
                walled += 1;
            }
        }
    }
    walled
}

#[cfg(test)]
mod tests {
    use super::*;
    use uniphys_geometry::TriMesh;

    /// A carcass open at the front (-y): sides, bottom, top and back boards 2 cm thick around a
    /// 0.5 m wide, 0.2 m tall, 0.4 m deep slot; a drawer box filling the slot with 5 mm of play.
    fn carcass_and_drawer() -> (TriMesh, TriMesh) {
        let board = |min: [f64; 3], max: [f64; 3]| {
            TriMesh::cuboid(DVec3::from_array(min), DVec3::from_array(max))
        };
        let carcass = TriMesh::merge(&[
            board([-0.02, 0.0, 0.0], [0.0, 0.4, 0.24]),
            board([0.5, 0.0, 0.0], [0.52, 0.4, 0.24]),
            board([0.0, 0.0, 0.0], [0.5, 0.4, 0.02]),
            board([0.0, 0.0, 0.22], [0.5, 0.4, 0.24]),
            board([-0.02, 0.4, 0.0], [0.52, 0.42, 0.24]),
        ]);
        let drawer = board([0.005, 0.0, 0.025], [0.495, 0.39, 0.215]);
        (carcass, drawer)
    }

    #[test]
    fn a_drawer_in_its_carcass_is_walled_in_on_every_side() {
        let (carcass, drawer) = carcass_and_drawer();
        let s = Scene::of_convex_parts(&[carcass, drawer], 1500);
        let moving = s.points_of(&[1]);
        assert_eq!(walled_sides(&s, &[0], &moving, DVec3::Y), 4);
    }

    /// The same carcass cut into its five boards, as a decomposition may leave it: the bottom
    /// board (part 0, the drawer's parent), the drawer (part 1), then the sides, top and back
    /// (parts 2 to 5).
    fn cut_carcass_and_drawer() -> Scene {
        let board = |min: [f64; 3], max: [f64; 3]| {
            TriMesh::cuboid(DVec3::from_array(min), DVec3::from_array(max))
        };
        let (_, drawer) = carcass_and_drawer();
        Scene::of_convex_parts(
            &[
                board([0.0, 0.0, 0.0], [0.5, 0.4, 0.02]),
                drawer,
                board([-0.02, 0.0, 0.0], [0.0, 0.4, 0.24]),
                board([0.5, 0.0, 0.0], [0.52, 0.4, 0.24]),
                board([0.0, 0.0, 0.22], [0.5, 0.4, 0.24]),
                board([-0.02, 0.4, 0.0], [0.52, 0.42, 0.24]),
            ],
            1500,
        )
    }

    #[test]
    fn a_drawer_in_a_cut_carcass_is_walled_in_by_the_boards_together() {
        let s = cut_carcass_and_drawer();
        let moving = s.points_of(&[1]);
        assert!(walled_sides(&s, &[0], &moving, DVec3::Y) <= 1);
        assert_eq!(walled_sides(&s, &[0, 2, 3, 4, 5], &moving, DVec3::Y), 4);
    }

    #[test]
    fn a_drawer_in_a_cut_carcass_slides_when_any_still_part_may_wall_it() {
        use uniphys_types::{Joint, JointKind, JointLimits, PartId, Provenance};

        use crate::sweep::sweep;
        use crate::sweep_params::SweepParams;

        let s = cut_carcass_and_drawer();
        let drawer_out = Joint {
            name: "drawer".to_owned(),
            kind: JointKind::Prismatic,
            parent: PartId(0),
            child: PartId(1),
            axis_in_object: [0.0, -1.0, 0.0],
            pivot_in_object_m: [0.25, 0.2, 0.12],
            limits: Some(JointLimits {
                lower: 0.0,
                upper: 0.3,
            }),
            damping: 0.0,
            friction: 0.0,
            coupled_parts: Vec::new(),
            provenance: Provenance::rule("test"),
        };
        let in_no_slot = |params: &SweepParams| {
            let metrics = sweep(&s, &drawer_out, &[1], params).expect("sweep");
            metrics
                .failures(params)
                .iter()
                .any(|r| r.contains("runs in no slot"))
        };
        assert!(in_no_slot(&SweepParams::default()));
        assert!(!in_no_slot(&SweepParams {
            slot_walled_by_any_still_part: true,
            ..SweepParams::default()
        }));
    }

    #[test]
    fn a_door_pushed_along_its_face_is_in_no_slot() {
        // The same carcass with a door 1 cm thick in front of its opening, slid upwards (z).
        let (carcass, _) = carcass_and_drawer();
        let door = TriMesh::cuboid(
            DVec3::new(-0.02, -0.012, 0.0),
            DVec3::new(0.52, -0.002, 0.24),
        );
        let s = Scene::of_convex_parts(&[carcass, door], 1500);
        let moving = s.points_of(&[1]);
        let walled = walled_sides(&s, &[0], &moving, DVec3::Z);
        assert!(walled <= 1, "{walled}");
    }
}
