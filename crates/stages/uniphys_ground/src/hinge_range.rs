//! How far a chosen hinge turns, each way from rest, and which way is open (reference:
//! real-articulated-objects.md: "it swings outward, away from the cavity", "the range is where
//! the sweep first collides").
//!
//! The hinge line is swept both ways, up to a full turn, finer than the search that chose it.
//! Each side's range is where the part first passes through another part or its axis leaves its
//! parent. Then the stops a real hinge has and an isolated mesh does not show:
//!
//! - a sheet (a part whose surface fills its box's broad faces) closed at rest on a face of its
//!   parent's box (a door, a flap, a lid) opens outward only, away from its parent, and a
//!   quarter turn at most: the stop of a door's hinges, which an object standing alone cannot
//!   show (a door of a hollow cabinet could otherwise swing into it);
//! - another broad sheet (a laptop screen, a lid propped open) closes until it meets its parent
//!   or first lies on a face of its parent's box (a lid over an open box meets only the rim,
//!   flush, and the sweep sees nothing stop it there), and opens at most 135 degrees from there
//!   (past upright, where such hinges stop);
//! - anything else (a wire such as a bucket handle, a knife's blade, a lever) turns both ways
//!   until it collides; stopped both ways by one obstacle (the stops add up to a full turn), it
//!   turns only the way that folds it into the object ([`folding_way`]);
//! - where the free turns either way overlap, so that nothing the sweep sees stops it, the range
//!   of the search that chose the hinge stands (checked before the two rules above).

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use uniphys_geometry::{DQuat, DVec3, parallel_map, projection_range};
use uniphys_types::{Joint, JointLimits};
use uniphys_verify::{Scene, SweepParams, sweep};

use crate::hypotheses::mean;
use crate::motion_search::{Mover, PartBox};

/// Steps of each side's sweep over a full turn (7.5 degrees apart).
const RANGE_STEPS: usize = 49;
/// A panel whose middle box extent is at least this share of its longest is broad (a door, a
/// lid); narrower ones are blades and levers.
const BROAD_RATIO: f64 = 0.3;
/// A part whose surface area is at least this share of its box's two broad faces is a sheet (a
/// door, a screen); below it, a frame or a wire (a bucket handle).
const SHEET_FILL_MIN: f64 = 0.3;
/// A panel open at rest opens this far from where it closes (135 degrees: past upright, where a
/// laptop's or a box lid's hinge stops).
const OPEN_FROM_CLOSED_RAD: f64 = 0.75 * PI;
/// Poses along each way at which a part stopped by one obstacle is checked for lying within
/// its object's box ([`folding_way`]) ...
const FOLD_POSES: usize = 12;
/// ... and by how much more of it one way must keep inside to be taken over the shorter way.
const FOLD_INSIDE_MARGIN: f64 = 0.05;
/// A panel set back from its parent's box closes a side of it when, over its outline, at most
/// this share of its parent's samples lie in front of it (against those behind it).
const IN_FRONT_SHARE_MAX: f64 = 0.02;
/// Angles at which a panel open at rest is tried closed onto its parent's face (2 degrees).
const CLOSING_STEP_RAD: f64 = PI / 90.0;
/// A panel lies on a face of its parent's box when its thin axis is within this angle of the
/// face's normal (cosine of 15 degrees) ...
const ON_FACE_COS: f64 = 0.965_925_8;
/// ... and its middle is within this share of the parent's extent along that normal (plus the
/// panel's own thickness) of the face.
const ON_FACE_FRACTION: f64 = 0.1;

/// The chosen hinge with its axis turned to open positively and its range `[lower, upper]`
/// (radians, rest at 0), and a few words on what bounded it. `closes_side`: whether the part
/// closes a side of its parent ([`closed_side`], found by the caller).
pub(crate) fn hinge_range(
    scene: &Scene,
    mover: &Mover<'_>,
    hinge: &Joint,
    part: &PartBox,
    parent: &PartBox,
    child_points: &[DVec3],
    closes_side: bool,
) -> (Joint, &'static str) {
    let axis = DVec3::from_array(hinge.axis_in_object);
    let Some(turns) = free_turns(scene, mover, hinge) else {
        return (hinge.clone(), "range kept from the search");
    };
    let (forward, backward) = (turns.forward, turns.backward);
    let params = range_params();
    let [_, middle, longest] = part.sorted_extents();
    let sheet = scene.area_m2(mover.child) >= SHEET_FILL_MIN * 2.0 * middle * longest;
    let broad = middle >= BROAD_RATIO * longest;
    // The side on which the part's middle first moves away from its parent's middle.
    let pivot = DVec3::from_array(hinge.pivot_in_object_m);
    let centre = mean(child_points);
    let away = axis.cross(centre - pivot).dot(centre - parent.centre) >= 0.0;
    let (open_axis, opens, closes) = if away {
        (axis, forward, backward)
    } else {
        (-axis, backward, forward)
    };
    let closed = on_parent_face(child_points, part, parent) || closes_side;
    let (open_axis, lower, upper, why) = if sheet && closed {
        (
            open_axis,
            0.0,
            opens.min(FRAC_PI_2),
            "closed on its parent's face: opens outward, a quarter turn at most (a hinge's stop)",
        )
    } else if turns.unbounded() {
        // The free turns either way overlap: a pose reached freely one way is where the other
        // way stopped, so the sweep cannot see what stops it (a blade folded inside its handle
        // has no surface clear of it to collide with). Stops that meet, one step short of each
        // other's, are one obstacle seen from both sides (a laptop's base, closed onto from
        // above and swung under from behind).
        return (
            hinge.clone(),
            "nothing seen stops it either way: the search's range",
        );
    } else if sheet && broad {
        // Closed where it first lies on a face of its parent's box, if the sweep lets it turn
        // so far: a lid over an open box meets only the rim, flush, and nothing stops it there.
        let closes =
            lies_on_parent(child_points, pivot, open_axis, closes, parent).unwrap_or(closes);
        (
            open_axis,
            closes,
            opens.min(OPEN_FROM_CLOSED_RAD - closes).max(0.0),
            "open at rest: closes onto its parent, opens 135 degrees from closed",
        )
    } else if turns.one_obstacle() {
        let (a, upper) = folding_way(scene, mover, hinge, &turns);
        (
            a,
            0.0,
            upper,
            "stopped both ways by one obstacle: turns the way that folds it into the object",
        )
    } else {
        let (a, up, down) = if forward >= backward {
            (axis, forward, backward)
        } else {
            (-axis, backward, forward)
        };
        (a, down, up, "turns both ways until it collides")
    };
    let with_range = |lower: f64, upper: f64| {
        let mut joint = hinge.clone();
        joint.axis_in_object = open_axis.to_array();
        joint.limits = Some(JointLimits { lower, upper });
        joint
    };
    // The verifier also judges the contact over the whole range: a range it would fail gives way
    // to the opening side alone, then to the search's own range. Where all fail on this coarse
    // scene, the reasoned range stands and the verifier, with its denser samples, judges it.
    let mut choices = vec![(with_range(-lower, upper), why)];
    if lower > 0.0 {
        choices.push((
            with_range(0.0, upper),
            "the closing side fails the contact checks: opens only",
        ));
    }
    choices.push((
        hinge.clone(),
        "the sweeps' ranges fail the contact checks: the search's range",
    ));
    let passes = |j: &Joint| {
        let range = j.limits.map_or(0.0, |l| l.upper - l.lower);
        range > 0.0
            && sweep(scene, j, mover.moving, &params).is_ok_and(|m| m.failures(&params).is_empty())
    };
    choices
        .iter()
        .find(|(j, _)| passes(j))
        .cloned()
        .unwrap_or_else(|| choices[0].clone())
}

/// How far a hinge turns freely each way from rest, radians (each one step short of where the
/// sweep first fails, a full turn when nothing stops it), and the sweep's step.
pub(crate) struct FreeTurns {
    pub forward: f64,
    pub backward: f64,
    pub step: f64,
}

impl FreeTurns {
    /// Whether the free turns either way overlap: nothing the sweep sees stops the part.
    pub(crate) fn unbounded(&self) -> bool {
        self.forward + self.backward > TAU + 2.0 * self.step
    }

    /// Whether the stops either way add up to a full turn: one obstacle met from both sides.
    pub(crate) fn one_obstacle(&self) -> bool {
        self.forward + self.backward >= TAU - 2.0 * self.step
    }
}

/// Of the two ways a part stopped both ways by one obstacle can turn, the one that folds it into
/// the object: along the way, more of it stays within the object's box at rest. Both ways end
/// at the obstacle; one swings the part out and round it, the other folds it over the object (a
/// glasses' temple folds behind the frame, not out to the side and round in front of it).
/// Folding parts fold to keep their object compact; where a real hinge has its stop, the sweep
/// sees nothing. Equal ways: the shorter. Returns the hinge's axis turned so that this way is
/// positive, and how far it turns.
pub(crate) fn folding_way(
    scene: &Scene,
    mover: &Mover<'_>,
    hinge: &Joint,
    turns: &FreeTurns,
) -> (DVec3, f64) {
    let axis = DVec3::from_array(hinge.axis_in_object);
    let pivot = DVec3::from_array(hinge.pivot_in_object_m);
    let everything: Vec<usize> = (0..scene.part_count()).collect();
    let object = PartBox::of(&scene.points_of(&everything));
    let moving = scene.points_of(mover.moving);
    // The mean share of the moving samples inside the object's box over the way's poses.
    let inside_along = |a: DVec3, angle: f64| {
        let inside: usize = (1..=FOLD_POSES)
            .map(|i| {
                let turn = DQuat::from_axis_angle(a, angle * i as f64 / FOLD_POSES as f64);
                moving
                    .iter()
                    .filter(|p| object.contains(pivot + turn * (**p - pivot)))
                    .count()
            })
            .sum();
        inside as f64 / (FOLD_POSES * moving.len()).max(1) as f64
    };
    let forward = (axis, turns.forward, inside_along(axis, turns.forward));
    let backward = (-axis, turns.backward, inside_along(-axis, turns.backward));
    let (shorter, longer) = if turns.forward <= turns.backward {
        (forward, backward)
    } else {
        (backward, forward)
    };
    let way = if longer.2 > shorter.2 + FOLD_INSIDE_MARGIN {
        longer
    } else {
        shorter
    };
    (way.0, way.1)
}

/// The sweep settings of the range sweeps: a full turn in [`RANGE_STEPS`] steps.
fn range_params() -> SweepParams {
    SweepParams {
        steps: RANGE_STEPS,
        ..SweepParams::default()
    }
}

/// The hinge swept each way up to a full turn; `None` when a sweep cannot run.
pub(crate) fn free_turns(scene: &Scene, mover: &Mover<'_>, hinge: &Joint) -> Option<FreeTurns> {
    let axis = DVec3::from_array(hinge.axis_in_object);
    let sides = [axis, -axis].map(|a| {
        let mut j = hinge.clone();
        j.axis_in_object = a.to_array();
        j.limits = Some(JointLimits {
            lower: 0.0,
            upper: TAU,
        });
        j
    });
    let params = range_params();
    let step = TAU / (RANGE_STEPS - 1) as f64;
    let free = parallel_map(&sides, |j| {
        let m = sweep(scene, j, mover.moving, &params).ok()?;
        Some(
            m.failure_coordinate()
                .map_or(TAU, |q| (q.abs() - step).max(0.0)),
        )
    });
    Some(FreeTurns {
        forward: free[0]?,
        backward: free[1]?,
        step,
    })
}

/// The smallest turn, up to `max_rad`, that closes a panel onto a face of its parent's box: the
/// panel turned back about `open_axis` through `pivot` by growing angles lies on the face
/// ([`on_parent_face`]), taken where its thin axis is best aligned with the face's normal
/// within the first stretch of angles that do. `None` when no turn up to `max_rad` does.
fn lies_on_parent(
    child_points: &[DVec3],
    pivot: DVec3,
    open_axis: DVec3,
    max_rad: f64,
    parent: &PartBox,
) -> Option<f64> {
    let steps = (max_rad / CLOSING_STEP_RAD).floor() as usize;
    let mut best: Option<(f64, f64)> = None;
    for i in 1..=steps {
        let angle = i as f64 * CLOSING_STEP_RAD;
        let turn = DQuat::from_axis_angle(open_axis, -angle);
        let turned: Vec<DVec3> = child_points
            .iter()
            .map(|p| pivot + turn * (*p - pivot))
            .collect();
        let part = PartBox::of(&turned);
        if !on_parent_face(&turned, &part, parent) {
            if best.is_some() {
                break;
            }
            continue;
        }
        let thin = part.axes[part.thinnest_axis()];
        let alignment = parent
            .axes
            .iter()
            .map(|a| a.dot(thin).abs())
            .fold(0.0, f64::max);
        if best.is_none_or(|(_, b)| alignment > b) {
            best = Some((angle, alignment));
        }
    }
    best.map(|(angle, _)| angle)
}

/// Whether a panel lies on a face of its parent's box: its thin axis along the face's normal, its
/// middle near the face (an inset door just inside it, an overlay door just outside) and over
/// it (not beside it, as a door swung open).
fn on_parent_face(child_points: &[DVec3], part: &PartBox, parent: &PartBox) -> bool {
    let thin = part.thinnest_axis();
    (0..3).any(|k| {
        let normal = parent.axes[k];
        if part.axes[thin].dot(normal).abs() < ON_FACE_COS {
            return false;
        }
        let (lo, hi) = projection_range(child_points, normal);
        let middle = 0.5 * (lo + hi);
        let tolerance = ON_FACE_FRACTION * parent.extent(k) + (hi - lo);
        let (face_lo, face_hi) = parent.ranges[k];
        let near_face =
            (middle - face_lo).abs() <= tolerance || (middle - face_hi).abs() <= tolerance;
        near_face && over_face(part, parent, k)
    })
}

/// The normal of the side of its parent a panel closes from outside, if it closes one: its thin
/// axis along a normal of the parent's box, its middle over that face, something still behind
/// it and nothing still in front of it over its outline (`still_points`: samples of the parts
/// that do not move with it, its parent among them). A door on its cabinet's front closes it,
/// and so does one set back from its parent's box (under a table's overhanging top, more than
/// [`ON_FACE_FRACTION`] of the table's depth in from its edge); a drawer's top under its
/// cabinet's top closes nothing.
pub(crate) fn closed_side(
    child_points: &[DVec3],
    part: &PartBox,
    parent: &PartBox,
    still_points: &[DVec3],
) -> Option<DVec3> {
    let thin = part.thinnest_axis();
    let across = [(thin + 1) % 3, (thin + 2) % 3];
    let in_outline = |p: &DVec3| {
        across.iter().all(|&m| {
            let x = p.dot(part.axes[m]);
            x >= part.ranges[m].0 && x <= part.ranges[m].1
        })
    };
    (0..3)
        .map(|k| parent.axes[k])
        .enumerate()
        .find_map(|(k, normal)| {
            if part.axes[thin].dot(normal).abs() < ON_FACE_COS || !over_face(part, parent, k) {
                return None;
            }
            let (lo, hi) = projection_range(child_points, normal);
            let (face_lo, face_hi) = parent.ranges[k];
            // It faces the nearer face of its parent's box.
            let outward_up = face_hi - hi <= lo - face_lo;
            let (mut in_front, mut behind) = (0_usize, 0_usize);
            for p in still_points.iter().filter(|p| in_outline(p)) {
                let x = p.dot(normal);
                if (outward_up && x > hi) || (!outward_up && x < lo) {
                    in_front += 1;
                } else {
                    behind += 1;
                }
            }
            (behind > 0 && in_front as f64 <= IN_FRONT_SHARE_MAX * behind as f64).then_some(normal)
        })
}

/// Whether the middle of a part lies over the face of its parent's box normal to axis `k`: within
/// the box's range along the other two axes (a door closed on it, not one swung out beside it).
fn over_face(part: &PartBox, parent: &PartBox, k: usize) -> bool {
    (0..3).filter(|&m| m != k).all(|m| {
        let c = part.centre.dot(parent.axes[m]);
        c >= parent.ranges[m].0 && c <= parent.ranges[m].1
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_points::box_grid;

    /// Points filling the box `[lo, hi]` on a grid.
    fn grid(lo: DVec3, hi: DVec3) -> Vec<DVec3> {
        box_grid(lo, hi, 6)
    }

    #[test]
    fn a_panel_on_its_parents_face_is_closed_and_one_standing_off_it_is_not() {
        let body = PartBox::of(&grid(DVec3::ZERO, DVec3::new(0.5, 0.6, 1.0)));
        let door = grid(DVec3::new(0.5, 0.0, 0.0), DVec3::new(0.52, 0.6, 1.0));
        assert!(on_parent_face(&door, &PartBox::of(&door), &body));
        let inset = grid(DVec3::new(0.46, 0.02, 0.02), DVec3::new(0.48, 0.58, 0.98));
        assert!(on_parent_face(&inset, &PartBox::of(&inset), &body));
        // The same door swung a quarter turn stands out of the face, edge on.
        let open = grid(DVec3::new(0.5, 0.0, 0.0), DVec3::new(1.1, 0.02, 1.0));
        assert!(!on_parent_face(&open, &PartBox::of(&open), &body));
        // A blade folded into the middle of its handle lies on no face.
        let blade = grid(DVec3::new(0.24, 0.05, 0.1), DVec3::new(0.26, 0.55, 0.9));
        assert!(!on_parent_face(&blade, &PartBox::of(&blade), &body));
    }

    #[test]
    fn a_lid_standing_at_the_back_rim_closes_when_it_lies_on_the_top() {
        // A box 1 x 1 x 0.6 with its lid standing up along its back edge (x = 0).
        let body = PartBox::of(&grid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.6)));
        let lid = grid(DVec3::new(0.0, 0.0, 0.6), DVec3::new(0.02, 1.0, 1.6));
        let pivot = DVec3::new(0.0, 0.5, 0.6);
        // It opens by turning its top away from the box (towards -x): about -y.
        let closes = lies_on_parent(&lid, pivot, -DVec3::Y, PI, &body).expect("it closes");
        assert!(
            (closes - FRAC_PI_2).abs() <= CLOSING_STEP_RAD,
            "closes {:.1} deg",
            closes.to_degrees()
        );
        // Turned back only 60 degrees, it lies on no face.
        assert!(lies_on_parent(&lid, pivot, -DVec3::Y, PI / 3.0, &body).is_none());
    }

    #[test]
    fn a_door_set_back_under_an_overhanging_top_closes_its_side() {
        // A cabinet 0.6 deep (y in [0, 0.6]) under a top overhanging its front by 0.15: the
        // door on the cabinet's front (y = 0) is 0.15 in from the front of the parent's box.
        let mut table = grid(DVec3::ZERO, DVec3::new(0.5, 0.6, 0.7));
        table.extend(grid(
            DVec3::new(-0.1, -0.15, 0.7),
            DVec3::new(0.6, 0.6, 0.75),
        ));
        let body = PartBox::of(&table);
        let door = grid(DVec3::new(0.02, -0.02, 0.02), DVec3::new(0.48, 0.0, 0.68));
        let part = PartBox::of(&door);
        assert!(!on_parent_face(&door, &part, &body));
        assert!(closed_side(&door, &part, &body, &table).is_some());
        // A shelf reaching out in front of it: the door is inside its parent, not closing it.
        table.extend(grid(
            DVec3::new(0.0, -0.15, 0.3),
            DVec3::new(0.5, -0.05, 0.32),
        ));
        assert!(closed_side(&door, &part, &PartBox::of(&table), &table).is_none());
    }
}
