//! How a part nobody named moves: its joint chosen from its shape, its place on its parent and
//! sweeps of the candidate motions (reference: real-articulated-objects.md, "Cues that separate
//! the motions").
//!
//! 1. **Spin**: a part round about an axis turns continuously about it ([`crate::spin`]), unless it
//!    is small (its box diagonal under a fifth of its parent's), sits on a face of its parent and
//!    gives a hand nothing to turn it by: smooth all round and squat (a round button).
//! 2. **Push or turn**: such a button, or a small part that is not round and flat, moves a short
//!    way into its parent along the normal of the face it sits on (a button or a key); one that
//!    is not round but stands out of the face by 40 % of its width or more is a knob with a grip
//!    and turns about that normal ([`crate::small_part`]).
//! 3. **Twist**: a part held by one small flat patch of contact (a stem: a faucet's lever, a
//!    blade on its pin) twists about the patch's normal through its middle when that turn is
//!    free by a quarter turn or more ([`crate::stem`]).
//! 4. Otherwise every hinge line of the part's box (for each box axis but a thin panel's
//!    normal, the 9 lines through its corners, edge and face middles and centre, both
//!    directions) and every slide along a box axis (its parent's box axis when within 5 degrees
//!    of it) is swept outward from rest. Each gets its free range: how far it moves before it
//!    passes through another part, or (a hinge) its axis leaves the parent, or (a slide) it
//!    loses contact with the parent.
//!    - A part that is not a thin panel (thickness at least 15 % of its width) and lies mostly
//!      inside its parent's box (a drawer, a tray) slides when it can slide out of its opening:
//!      along a box axis in which its parent encloses it least (within 5 % of its length of
//!      the least), in which it is deep (at least 15 % of its longest extent, and not a slab's
//!      thickness), keeping touching the parent over half that depth; of those, the one that
//!      comes out the most of its depth, less how far the parent encloses it that way.
//!      Else it hinges when some hinge turns it freely by 30 degrees or more.
//!    - A thin panel (a door, a lid, a screen) or a part outside its parent (a handle) hinges
//!      first, then slides, by the same tests.
//!    - A part that can do neither is fixed.
//!
//!    Among hinges, the one with the widest free turn (up to a quarter turn) whose line runs along
//!    its parent and through where the part touches it at both ends of the contact wins; a line
//!    far from the handle (standing out of the outer face, or a part it carries) weighs as much
//!    as a quarter turn, and a line along the long edge breaks ties. A slide's range is its free
//!    range; a hinge is swept again both ways for its range ([`crate::hinge_range`]).

use std::f64::consts::{FRAC_PI_2, PI};

use uniphys_geometry::{Aabb, DVec3, extent_along, parallel_map, projection_range};
use uniphys_types::{Joint, JointKind};
pub(crate) use uniphys_verify::PartBox;
use uniphys_verify::{SMALL_PART_FRACTION, Scene, SweepMetrics, SweepParams, sweep};

use crate::articulate::builtin_joint;
use crate::hinge_range::{closed_side, hinge_range};
use crate::hypotheses::mean;
use crate::small_part::small_part_motion;
use crate::spin::spin_axis;
use crate::stem::{stem, twist_joint};

/// A part whose thinnest box extent is under this fraction of the middle one is a panel (a
/// door, a lid, a screen): it hinges first, slides only when it cannot hinge.
const THIN_RATIO: f64 = 0.15;
/// A part that is not a panel, with at least this share of its surface inside its parent's box sits in an opening of
/// its parent (a drawer, a tray): it slides first, hinges only when it cannot slide.
const INSIDE_SHARE_MIN: f64 = 0.5;
/// Parts within this fraction of the object's diagonal touch.
pub(crate) const TOUCH_FRACTION: f64 = 0.01;
/// A slide is supported while at least this many of the part's samples touch its parent.
const SUPPORT_POINTS_MIN: usize = 6;
/// Hinges are swept from rest to half a turn.
const HINGE_SWEEP_RAD: f64 = PI;
/// A hinge must turn freely at least this far to count, radians (30 degrees).
const HINGE_FREE_MIN_RAD: f64 = std::f64::consts::FRAC_PI_6;
/// A twist on a stem must turn at least this far freely to count, radians (a quarter turn).
const TWIST_FREE_MIN_RAD: f64 = FRAC_PI_2;
/// A slide must keep touching its parent over at least this share of the part's depth along it.
const SLIDE_FREE_MIN_FRACTION: f64 = 0.5;
/// A part slides only along a direction in which it is at least this deep, as a share of its
/// longest extent (a drawer's depth, not a door's thickness).
const SLIDE_DEPTH_MIN_FRACTION: f64 = 0.15;
/// A part whose thinnest box extent is under this fraction of the middle one is a slab: it has
/// an outer face that can carry a handle ([`uniphys_verify::panel_handle`]), and it does not
/// slide along its thinnest axis (a thick door is not a drawer) ...
pub(crate) const SLAB_RATIO: f64 = uniphys_verify::PANEL_SLAB_RATIO;
/// ... which is a direction in which it is no deeper than this many times its thinnest extent
/// (box axes and slide axes agree to a few percent).
const SLAB_DEPTH_SLACK: f64 = 1.1;
/// Contacts within this share of the contact's extent from either end of a hinge axis hold the
/// hinge.
const HINGE_END_FRACTION: f64 = 0.15;
/// Weight of the handle's distance from a hinge line (as a share of the part's width) in a
/// hinge's score: a handle is put where it gives the most leverage, at the edge across from the
/// hinge, so it outweighs the long-edge tie-break (0.3).
const HANDLE_WEIGHT: f64 = 1.0;
/// A slide along a part's box axis within this angle of one of its parent's box axes (cosine of
/// 5 degrees) runs along the parent's.
const SLIDE_SNAP_COS: f64 = 0.996_194_7;
/// Slides whose parent reaches past the part by at most this share of the part's length more
/// than along the least enclosed slide are ways out of its opening (a drawer's front and a
/// side flush with its table's; not a door's face, which stands proud of its cabinet while its
/// edges are flush with the cabinet's).
const OPENING_SLACK_FRACTION: f64 = 0.05;
/// A slide runs along the side its part closes when it is more than 60 degrees from that side's
/// normal (cosine): slides run along box axes, so along the side or out of it.
const ALONG_SIDE_COS: f64 = 0.5;
/// Steps of each candidate's sweep.
const STEPS: usize = 16;

/// The part being articulated.
pub(crate) struct Mover<'a> {
    pub(crate) child: usize,
    pub(crate) parent: usize,
    /// The child and the parts it carries.
    pub(crate) moving: &'a [usize],
    /// Every part's box, by part index (computed once per asset).
    pub(crate) boxes: &'a [PartBox],
}

/// The chosen joint (`None` for fixed) and a one-line account of the choice for the report.
pub(crate) struct Motion {
    pub(crate) joint: Option<Joint>,
    pub(crate) summary: String,
}

/// A swept candidate and what it showed.
struct Candidate {
    joint: Joint,
    /// Free range: radians for hinges, metres for slides.
    free: f64,
    /// Ranking score within its kind (higher is better).
    score: f64,
}

/// The joint of `mover`, or `None` (fixed) when no motion fits.
pub(crate) fn find_motion(scene: &Scene, mover: &Mover<'_>) -> Motion {
    let child_points = scene.points_of(&[mover.child]);
    let parent_points = scene.points_of(&[mover.parent]);
    if child_points.len() < 16 || parent_points.is_empty() {
        return Motion {
            joint: None,
            summary: "too little surface to judge a motion; fixed".to_owned(),
        };
    }
    let part = &mover.boxes[mover.child];
    let inward = toward_parent(scene, mover, &child_points, part);
    let parent_diagonal = Aabb::from_points(&parent_points).diagonal();
    let small = part.diagonal < SMALL_PART_FRACTION * parent_diagonal;
    let spin = spin_axis(scene, mover.child, &child_points, part, inward);
    let button = spin.is_some_and(|s| s.pressed(scene, mover.parent, &child_points, part.diagonal));
    if let Some(spin) = spin.filter(|_| !button) {
        return Motion {
            joint: Some(joint(
                mover,
                JointKind::Continuous,
                spin.axis,
                spin.centre,
                None,
                "round about this axis: spins".to_owned(),
            )),
            summary: format!(
                "round about an axis ({:.0} % of its surface maps onto itself when turned): continuous",
                100.0 * spin.kept_fraction
            ),
        };
    }
    if small {
        return small_part_motion(
            scene,
            mover,
            &child_points,
            part,
            spin,
            inward,
            part.diagonal / parent_diagonal.max(1e-12),
        );
    }
    let touch_m = TOUCH_FRACTION * scene.diagonal_m;
    // Where the part touches its parent: a hinge runs through it (a bucket handle's two ends, a
    // screen's lower edge), and a small flat patch of it is a stem the part may twist on.
    let touching = touching(scene, mover.parent, &child_points, touch_m);
    let mut hypotheses = hypotheses(mover, part);
    let box_lines = hypotheses.len();
    if let Some(stem) = stem(&touching, part) {
        for sign in [1.0, -1.0] {
            hypotheses.push(joint(
                mover,
                JointKind::Revolute,
                stem.normal * sign,
                stem.centre,
                Some(HINGE_SWEEP_RAD),
                "twist about the stem it is held by, chosen by its free sweep".to_owned(),
            ));
        }
    }
    let params = SweepParams {
        steps: STEPS,
        ..SweepParams::default()
    };
    let swept = parallel_map(&hypotheses, |j| {
        let metrics = sweep(scene, j, mover.moving, &params).ok()?;
        let supported = (j.kind == JointKind::Prismatic)
            .then(|| supported_travel(scene, mover, &child_points, j, touch_m));
        Some((metrics, supported))
    });
    // A handle (standing out of the part's outer face, or a part it carries) sits near the free
    // edge, away from the hinge.
    let handle = handle_centre(
        scene,
        mover,
        &child_points,
        part.centre - mean(&parent_points),
    );
    let parent_box = &mover.boxes[mover.parent];
    let inside = inside_share(&child_points, parent_box);
    let longest = part.sorted_extents()[2].max(1e-12);
    let mut hinges = Vec::new();
    let mut twists = Vec::new();
    let mut slides = Vec::new();
    for (index, (joint, metrics)) in hypotheses.into_iter().zip(swept).enumerate() {
        let twist = index >= box_lines;
        let Some((m, supported)) = metrics.filter(|(m, _)| m.initial_contact_points > 0) else {
            continue;
        };
        let upper = joint.limits.map_or(0.0, |l| l.upper);
        let free = free_range(&m, upper).min(supported.unwrap_or(f64::INFINITY));
        let axis = DVec3::from_array(joint.axis_in_object);
        if twist {
            // Both ways about the stem's line: the freer one is the candidate.
            twists.push(Candidate {
                score: free,
                free,
                joint,
            });
        } else if joint.kind == JointKind::Prismatic {
            // How far the parent reaches past the part that way: an opening's way out has
            // (nearly) none.
            let margin = support(&parent_points, axis) - support(&child_points, axis);
            let depth = extent_along(&child_points, axis).max(1e-12);
            slides.push((
                Candidate {
                    score: free.min(depth) / depth - margin / longest,
                    free,
                    joint,
                },
                margin,
            ));
        } else {
            let pivot = DVec3::from_array(joint.pivot_in_object_m);
            let line = |p: DVec3| (p - pivot).reject_from_normalized(axis).length();
            let width = (0..3)
                .map(|k| part.axes[k].reject_from_normalized(axis).length() * part.extent(k))
                .fold(0.0, f64::max)
                .max(1e-12);
            let from_handle = handle.map_or(0.0, |h| line(h) / width);
            let along = (0..3)
                .map(|k| part.axes[k].dot(axis).abs() * part.extent(k))
                .fold(0.0, f64::max);
            let from_contact = contact_off_line(&touching, pivot, axis);
            let score = free.min(FRAC_PI_2) / FRAC_PI_2
                - 2.0 * m.hinge_mean_to_parent_m / part.diagonal.max(1e-12)
                - 2.0 * from_contact / part.diagonal.max(1e-12)
                + 0.3 * along / longest
                + HANDLE_WEIGHT * from_handle.min(1.0);
            hinges.push(Candidate { joint, free, score });
        }
    }
    let best = |list: &mut Vec<Candidate>| {
        list.sort_by(|a, b| b.score.total_cmp(&a.score));
        list.first().map(|c| (c.joint.clone(), c.free, c.score))
    };
    // A part held by a stem twists on it when it turns a quarter turn freely: a twist stopped
    // sooner is a patch that only looks like a stem (a lid's hinge seen through few samples).
    if let Some((twist, free, _)) =
        best(&mut twists).filter(|(_, free, _)| *free >= TWIST_FREE_MIN_RAD)
    {
        let (joint, why) = twist_joint(scene, mover, &twist);
        return Motion {
            joint: Some(joint),
            summary: format!(
                "held by one small flat patch, a stem: twists on it ({why}; turns {:.0} deg freely in the search)",
                free.to_degrees()
            ),
        };
    }
    let hinge = best(&mut hinges).filter(|(_, free, _)| *free >= HINGE_FREE_MIN_RAD);
    // A part slides out of its opening along its depth: only the way out counts, and it must be
    // deep that way (a door's way out is through its thin face) and travel most of that depth.
    // A slab (a thick door) does not slide out through its own face: only its thickness would
    // clear the opening.
    let [thin, middle, _] = part.sorted_extents();
    let slab = thin < SLAB_RATIO * middle;
    // A part that closes a side of its parent from outside (a door on its front) slides, if at
    // all, out of that side: slid along it, it is a door pushed sideways or down out of its
    // frame, which only the ground, when there is one, would stop. A drawer closes no side by
    // this test (its thin axis is its height, not its depth). What lies in front of the part is
    // looked for in everything that stays still, not its parent alone: a decomposition may hang a
    // drawer from a table's lower frame and leave the top another part, and the drawer under
    // that top closes nothing.
    let still_points = scene.points_of(&scene.still_parts(mover.moving));
    let closed = closed_side(&child_points, part, parent_box, &still_points);
    let along_closed_side =
        |axis: DVec3| closed.is_some_and(|n| axis.dot(n).abs() < ALONG_SIDE_COS);
    // Ways out of the opening: those where the parent reaches past the part least (within
    // `OPENING_SLACK_FRACTION` of the part's length of the least), deep and free enough; of
    // them, the one the part comes out of the most.
    let least = slides
        .iter()
        .map(|(_, margin)| *margin)
        .fold(f64::INFINITY, f64::min);
    let mut slides: Vec<Candidate> = slides
        .into_iter()
        .filter(|(c, margin)| {
            let depth = extent_along(&child_points, DVec3::from_array(c.joint.axis_in_object));
            *margin <= least + OPENING_SLACK_FRACTION * longest
                && depth >= SLIDE_DEPTH_MIN_FRACTION * longest
                && c.free >= SLIDE_FREE_MIN_FRACTION * depth
                && !(slab && depth <= SLAB_DEPTH_SLACK * thin)
                && !along_closed_side(DVec3::from_array(c.joint.axis_in_object))
        })
        .map(|(c, _)| c)
        .collect();
    let slide = best(&mut slides);
    let panel = panel_normal(part).is_some();
    let enclosed = !panel && inside >= INSIDE_SHARE_MIN;
    let chosen = if enclosed {
        slide.clone().or_else(|| hinge.clone())
    } else {
        hinge.clone().or_else(|| slide.clone())
    };
    let account = format!(
        "{}, {:.0} % inside its parent's box; best hinge {}; best slide {}",
        if panel {
            "a thin panel"
        } else {
            "not a thin panel"
        },
        100.0 * inside,
        hinges.first().map_or("none".to_owned(), |c| format!(
            "turns {:.0} deg freely (score {:.2})",
            c.free.to_degrees(),
            c.score
        )),
        slides.first().map_or("none".to_owned(), |c| format!(
            "out of its opening, keeps touching over {:.3}",
            c.free
        )),
    );
    match chosen {
        Some((mut joint, free, _)) => {
            let kind = if joint.kind == JointKind::Prismatic {
                if let Some(limits) = joint.limits.as_mut() {
                    limits.upper = free;
                }
                "slides".to_owned()
            } else {
                let why;
                (joint, why) = hinge_range(
                    scene,
                    mover,
                    &joint,
                    part,
                    parent_box,
                    &child_points,
                    closed.is_some(),
                );
                format!("hinges ({why})")
            };
            Motion {
                joint: Some(joint),
                summary: format!("{kind}: {account}"),
            }
        }
        None => Motion {
            joint: None,
            summary: format!("no free motion: fixed; {account}"),
        },
    }
}

/// The centre of the part's handle, if it has one: the parts it carries, or what stands out of
/// its outer face (turned away from the parent, `away`) against the face around it
/// ([`uniphys_verify::panel_handle`]).
fn handle_centre(
    scene: &Scene,
    mover: &Mover<'_>,
    child_points: &[DVec3],
    away: DVec3,
) -> Option<DVec3> {
    let carried: Vec<usize> = mover
        .moving
        .iter()
        .copied()
        .filter(|&p| p != mover.child)
        .collect();
    if !carried.is_empty() {
        return Some(mean(&scene.points_of(&carried)));
    }
    uniphys_verify::panel_handle(child_points, away)
}

/// How far the hinge line (through `pivot` along `axis`) passes from where the part touches its
/// parent at either end of the contact (its first and last [`HINGE_END_FRACTION`] along the
/// axis): the nearest contact at each end, averaged over the two ends. A hinge holds a part at
/// both ends of its axis (a bucket handle's two attachments), so a line clear of the contact at
/// an end is no hinge. The nearest contact, not the mean, counts: a door closed in its frame
/// touches along its whole rim, and every edge of it has contact at both its ends.
fn contact_off_line(touching: &[DVec3], pivot: DVec3, axis: DVec3) -> f64 {
    let line = |p: &DVec3| (*p - pivot).reject_from_normalized(axis).length();
    let (lo, hi) = projection_range(touching, axis);
    let end = HINGE_END_FRACTION * (hi - lo);
    let nearest = |at_end: &dyn Fn(f64) -> bool| {
        touching
            .iter()
            .filter(|p| at_end(p.dot(axis)))
            .map(line)
            .fold(f64::INFINITY, f64::min)
    };
    let (first, last) = (nearest(&|t| t <= lo + end), nearest(&|t| t >= hi - end));
    match (first.is_finite(), last.is_finite()) {
        (true, true) => 0.5 * (first + last),
        (true, false) => first,
        (false, true) => last,
        (false, false) => 0.0,
    }
}

/// The points within `touch_m` of the own triangles of part `other`.
pub(crate) fn touching(scene: &Scene, other: usize, points: &[DVec3], touch_m: f64) -> Vec<DVec3> {
    points
        .iter()
        .copied()
        .filter(|p| scene.distance_to_surface_m(other, *p) <= touch_m)
        .collect()
}

/// The largest `p . d` over the points.
fn support(points: &[DVec3], d: DVec3) -> f64 {
    projection_range(points, d).1
}

/// Share of the points inside the box (its axes and ranges).
fn inside_share(points: &[DVec3], b: &PartBox) -> f64 {
    let inside = points.iter().filter(|p| b.contains(**p)).count();
    inside as f64 / points.len().max(1) as f64
}

/// How far a slide moves the part while it still touches its parent (at least
/// `SUPPORT_POINTS_MIN` of its samples within `touch_m` of the parent's surface), one step short
/// of the first step where it does not.
fn supported_travel(
    scene: &Scene,
    mover: &Mover<'_>,
    child_points: &[DVec3],
    slide: &Joint,
    touch_m: f64,
) -> f64 {
    let axis = DVec3::from_array(slide.axis_in_object);
    let upper = slide.limits.map_or(0.0, |l| l.upper);
    let step = upper / (STEPS - 1) as f64;
    for i in 1..STEPS {
        let shift = axis * (step * i as f64);
        let touching = child_points
            .iter()
            .filter(|p| scene.distance_to_surface_m(mover.parent, **p + shift) <= touch_m)
            .take(SUPPORT_POINTS_MIN)
            .count();
        if touching < SUPPORT_POINTS_MIN {
            return step * (i - 1) as f64;
        }
    }
    upper
}

/// The signed box axis of the part that points at its parent: the one along which a small shift
/// of the part brings its samples closest to the parent's surface.
fn toward_parent(scene: &Scene, mover: &Mover<'_>, child: &[DVec3], part: &PartBox) -> DVec3 {
    let shift = 0.05 * part.sorted_extents()[0].max(0.01 * part.diagonal);
    let mean_gap = |d: DVec3| {
        child
            .iter()
            .map(|p| scene.distance_to_surface_m(mover.parent, *p + d * shift))
            .sum::<f64>()
    };
    part.axes
        .iter()
        .flat_map(|a| [*a, -*a])
        .min_by(|a, b| mean_gap(*a).total_cmp(&mean_gap(*b)))
        .unwrap_or(DVec3::Z)
}

/// Every hinge line of the part's box (9 per box axis, both directions) swept over half a turn,
/// and every slide along a box axis (both directions) over the part's length along it.
fn hypotheses(mover: &Mover<'_>, part: &PartBox) -> Vec<Joint> {
    let mut out = Vec::new();
    // A thin panel hinges about a line in its plane (a door, a lid, a screen). Turned about its
    // own normal it would wheel round in its plane like a clock hand, which only round parts
    // (spun) and parts held on a stem (twisted) do, and both are found before these lines.
    let normal = panel_normal(part);
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let levels = |r: (f64, f64)| [r.0, 0.5 * (r.0 + r.1), r.1];
        let along = part.axes[k] * (0.5 * (part.ranges[k].0 + part.ranges[k].1));
        let hinge_levels = if normal == Some(k) {
            Vec::new()
        } else {
            levels(part.ranges[u]).to_vec()
        };
        for su in hinge_levels {
            for sv in levels(part.ranges[v]) {
                let pivot = along + part.axes[u] * su + part.axes[v] * sv;
                for sign in [1.0, -1.0] {
                    out.push(joint(
                        mover,
                        JointKind::Revolute,
                        part.axes[k] * sign,
                        pivot,
                        Some(HINGE_SWEEP_RAD),
                        format!("hinge along box axis {k}, chosen by its free sweep"),
                    ));
                }
            }
        }
        let slide_axis = along_parent(part.axes[k], &mover.boxes[mover.parent]);
        for sign in [1.0, -1.0] {
            out.push(joint(
                mover,
                JointKind::Prismatic,
                slide_axis * sign,
                part.centre,
                Some(part.extent(k).max(1e-6)),
                format!("slide along box axis {k}, chosen by its free sweep"),
            ));
        }
    }
    out
}

/// The normal of a thin panel (its thinnest box axis, when under [`THIN_RATIO`] of its middle
/// extent: a door, a lid, a screen), or `None` for a part that is not one.
fn panel_normal(part: &PartBox) -> Option<usize> {
    let [thin, middle, _] = part.sorted_extents();
    (thin < THIN_RATIO * middle).then(|| part.thinnest_axis())
}

/// The parent's box axis within [`SLIDE_SNAP_COS`] of `axis` (signed as `axis`), else `axis`: a
/// part slides along its parent's runners, and a box fitted to the part alone can be a fraction
/// of a degree off them, enough for a drawer snug in its opening to scrape its side a few
/// centimetres out.
fn along_parent(axis: DVec3, parent: &PartBox) -> DVec3 {
    parent
        .axes
        .iter()
        .map(|a| if a.dot(axis) >= 0.0 { *a } else { -*a })
        .find(|a| a.dot(axis) >= SLIDE_SNAP_COS)
        .unwrap_or(axis)
}

/// How far the candidate moved before it failed (one step short of the failing coordinate): a
/// crossing, a hinge whose axis left its parent, a slide that lost contact, or a part taken
/// into the ground.
fn free_range(m: &SweepMetrics, upper: f64) -> f64 {
    let step = upper / (STEPS - 1) as f64;
    let failed = if m.kind == JointKind::Prismatic {
        // A slide stops where it passes through another part, leaves its parent or goes into
        // the ground (a door standing on the floor does not slide down through it).
        [
            m.crossing_coordinate,
            m.lost_contact_coordinate,
            m.below_ground_coordinate,
        ]
        .into_iter()
        .flatten()
        .map(f64::abs)
        .reduce(f64::min)
    } else {
        m.failure_coordinate().map(f64::abs)
    };
    failed.map_or(upper, |q| (q - step).max(0.0))
}

pub(crate) fn joint(
    mover: &Mover<'_>,
    kind: JointKind,
    axis: DVec3,
    pivot: DVec3,
    upper: Option<f64>,
    why: String,
) -> Joint {
    builtin_joint(kind, (mover.parent, mover.child), axis, pivot, upper, why)
}
