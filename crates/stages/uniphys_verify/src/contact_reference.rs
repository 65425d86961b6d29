//! The contact of a moving group with its parent at rest, which every sweep step is compared
//! with: its thickness across its own plane and how much of it a step's contact covers.

use uniphys_geometry::{Aabb, DVec3, KdTree, fit_plane, projection_range};
use uniphys_types::JointKind;

use crate::VerifyResult;
use crate::motion::JointMotion;
use crate::patch::{PosedTree, grow_patch, mean_spacing_m};

/// Parent points within this fraction of the moving group's diagonal of a turning joint's axis
/// line are the contact at the hinge (its barrel, a handle's two lugs, a screen's hinge line).
const HINGE_RADIUS_FRACTION: f64 = 0.1;
/// The contact at the hinge holds the part along its axis when it spans at least this share of
/// the group's extent along the axis.
const HINGE_SPAN_FRACTION: f64 = 0.5;
/// ... and the axis runs along the group, not across its thinnest side: its extent along the
/// axis is at least this share of its diagonal.
const HINGE_ALONG_FRACTION: f64 = 0.25;

/// The contact at rest that later steps are compared with.
pub(crate) struct ContactReference {
    /// The threshold that found the contact at rest, metres.
    pub(crate) threshold_m: f64,
    thickness_m: f64,
    points: Vec<DVec3>,
    tree: KdTree,
    overlap_radius_m: f64,
    /// A turning joint held along its axis: the contact at its hinge line.
    hinge: Option<HingeContact>,
}

/// The parent's points around a turning joint's axis line that touch the moving group at rest
/// (a hinge's barrel and frame, a handle's two lugs, a screen's hinge line).
struct HingeContact {
    /// The parent's points within the hinge radius of the axis line.
    tube: Vec<DVec3>,
    /// How near the moving group a point of the tube touches it, metres.
    threshold_m: f64,
    /// The tube's points touching the moving group at rest.
    at_rest: Vec<DVec3>,
    tree: KdTree,
}

impl ContactReference {
    /// The contact `points` (the parent's, found within `threshold_m` of the moving group at
    /// rest) of a joint moving by `motion`; `moving` holds the moving group's points at rest
    /// and `parent_points` the parent's, `search_m` the contact threshold search
    /// (first threshold, increment, increments: as [`grow_patch`]).
    pub(crate) fn new(
        points: &[DVec3],
        threshold_m: f64,
        motion: &JointMotion,
        moving: &KdTree,
        moving_points: &[DVec3],
        parent_points: &[DVec3],
        search_m: (f64, f64, usize),
    ) -> VerifyResult<Self> {
        Ok(Self {
            threshold_m,
            thickness_m: thickness_m(points)?,
            points: points.to_vec(),
            tree: KdTree::new(points.to_vec()),
            overlap_radius_m: 2.0 * mean_spacing_m(points),
            hinge: HingeContact::find(motion, moving, moving_points, parent_points, search_m),
        })
    }

    /// Thickness of a step's contact over the initial thickness, the latter at least the
    /// threshold that found the step's points (a band of points within a threshold of a surface
    /// is that thick; without the floor a thin initial contact makes any later one look thick).
    pub(crate) fn thickness_ratio(&self, points: &[DVec3], threshold_m: f64) -> VerifyResult<f64> {
        Ok(thickness_m(points)? / self.thickness_m.max(threshold_m))
    }

    /// How much of one contact the other covers: the larger of the fraction of the step's
    /// points (`points`, found near the moved group `moved`) near an initial point and the
    /// fraction of initial points near a step's point (within the overlap radius). A lid
    /// opening keeps part of its initial contact (the hinge line), a lid closing adds to it; a
    /// contact that slides elsewhere does neither. A part held along its hinge line also keeps
    /// its contact at that line, whatever it touches elsewhere as it swings past or onto other
    /// things (a bucket's handle laid against one side at rest and against the other at the end
    /// of its travel): the larger of both is taken.
    pub(crate) fn overlap_ratio(&self, points: &[DVec3], moved: &PosedTree<'_>) -> f64 {
        let whole = covered_either_way(&self.points, &self.tree, points, self.overlap_radius_m);
        match &self.hinge {
            Some(h) => {
                let now: Vec<DVec3> = h
                    .tube
                    .iter()
                    .copied()
                    .filter(|p| moved.nearest_distance_within(*p, h.threshold_m).is_some())
                    .collect();
                whole.max(covered_either_way(
                    &h.at_rest,
                    &h.tree,
                    &now,
                    self.overlap_radius_m,
                ))
            }
            None => whole,
        }
    }
}

impl HingeContact {
    /// The contact at the hinge, when `motion` turns the group about a line along which its
    /// parent holds it: the parent's points near the axis line that touch the group (within
    /// the first threshold of `search_m` that finds three) span most of the group's extent
    /// along the axis, and that extent is not the group's thin side (a door spun about its own
    /// normal is held at one spot, not along a line).
    fn find(
        motion: &JointMotion,
        moving: &KdTree,
        moving_points: &[DVec3],
        parent_points: &[DVec3],
        search_m: (f64, f64, usize),
    ) -> Option<Self> {
        if !matches!(motion.kind, JointKind::Revolute | JointKind::Continuous)
            || moving_points.is_empty()
        {
            return None;
        }
        let axis = motion.axis_in_object;
        let (lo, hi) = projection_range(moving_points, axis);
        let diagonal_m = Aabb::from_points(moving_points).diagonal();
        let along_m = hi - lo;
        if along_m < HINGE_ALONG_FRACTION * diagonal_m {
            return None;
        }
        let radius_m = HINGE_RADIUS_FRACTION * diagonal_m;
        let pivot = motion.pivot_in_object_m;
        let tube: Vec<DVec3> = parent_points
            .iter()
            .copied()
            .filter(|p| (*p - pivot).reject_from_normalized(axis).length() <= radius_m)
            .collect();
        let (start_m, step_m, max_increments) = search_m;
        let (at_rest, threshold_m) = grow_patch(&tube, moving, start_m, step_m, max_increments, 3)?;
        let (a, b) = projection_range(&at_rest, axis);
        (b - a >= HINGE_SPAN_FRACTION * along_m).then(|| Self {
            tube,
            threshold_m,
            tree: KdTree::new(at_rest.clone()),
            at_rest,
        })
    }
}

/// The larger of the share of `now` within `radius_m` of `at_rest` and the share of `at_rest`
/// within `radius_m` of `now` (0 when either is empty).
fn covered_either_way(at_rest: &[DVec3], tree: &KdTree, now: &[DVec3], radius_m: f64) -> f64 {
    if at_rest.is_empty() || now.is_empty() {
        return 0.0;
    }
    let covered = |of: &[DVec3], by: &KdTree| {
        of.iter()
            .filter(|p| by.nearest_distance_within(**p, radius_m).is_some())
            .count() as f64
            / of.len() as f64
    };
    covered(now, tree).max(covered(at_rest, &KdTree::new(now.to_vec())))
}

/// Spread of points across their least-squares plane, metres.
fn thickness_m(points: &[DVec3]) -> VerifyResult<f64> {
    let plane = fit_plane(points)?;
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let d = plane.distance(*p);
            (lo.min(d), hi.max(d))
        });
    Ok(if hi >= lo { hi - lo } else { 0.0 })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on the segment from `a` to `b`, `n` of them.
    fn line(a: DVec3, b: DVec3, n: usize) -> Vec<DVec3> {
        (0..n)
            .map(|i| a + (b - a) * (i as f64 / (n - 1) as f64))
            .collect()
    }

    /// A flap 1 m long along x, hinged on the x axis: lying towards -y at rest, turned half a
    /// turn it lies towards +y. The parent holds it at both ends of the hinge when `lugs`, and
    /// has a ledge under each side where the flap rests.
    fn flap_and_parent(lugs: bool) -> (Vec<DVec3>, Vec<DVec3>) {
        let flap: Vec<DVec3> = (0..=10)
            .flat_map(|i| {
                line(
                    DVec3::new(0.0, -0.05 * i as f64, 0.0),
                    DVec3::new(1.0, -0.05 * i as f64, 0.0),
                    21,
                )
            })
            .collect();
        let mut parent = Vec::new();
        for side in [-1.0, 1.0] {
            for y in [0.45, 0.5] {
                parent.extend(line(
                    DVec3::new(0.0, side * y, -0.01),
                    DVec3::new(1.0, side * y, -0.01),
                    21,
                ));
            }
        }
        if lugs {
            for x in [-0.01, 1.01] {
                parent.extend(line(DVec3::new(x, -0.01, 0.0), DVec3::new(x, 0.01, 0.0), 3));
            }
        }
        (flap, parent)
    }

    fn overlap_at_half_turn(lugs: bool) -> (f64, bool) {
        let (flap, parent) = flap_and_parent(lugs);
        let motion = JointMotion {
            kind: JointKind::Revolute,
            axis_in_object: DVec3::X,
            pivot_in_object_m: DVec3::ZERO,
        };
        let moving = KdTree::new(flap.clone());
        let touching = |tree: &KdTree| -> Vec<DVec3> {
            parent
                .iter()
                .copied()
                .filter(|p| tree.nearest_distance(*p) <= 0.02)
                .collect()
        };
        let reference = ContactReference::new(
            &touching(&moving),
            0.02,
            &motion,
            &moving,
            &flap,
            &parent,
            (0.02, 0.01, 0),
        )
        .expect("reference");
        let turned: Vec<DVec3> = flap
            .iter()
            .map(|p| {
                motion
                    .object_from_moved(std::f64::consts::PI)
                    .transform_point3(*p)
            })
            .collect();
        let moved = KdTree::new(turned);
        (
            reference.overlap_ratio(&touching(&moved), &PosedTree::at_rest(&moved)),
            reference.hinge.is_some(),
        )
    }

    #[test]
    fn a_flap_held_at_its_hinge_line_keeps_its_contact_there_while_its_rest_moves() {
        let (overlap, hinged) = overlap_at_half_turn(true);
        assert!(hinged);
        assert!(overlap > 0.9, "{overlap}");
        // Without the lugs nothing holds it along the axis: the contact moved from one ledge to
        // the other.
        let (overlap, hinged) = overlap_at_half_turn(false);
        assert!(!hinged);
        assert!(overlap < 0.4, "{overlap}");
    }
}
