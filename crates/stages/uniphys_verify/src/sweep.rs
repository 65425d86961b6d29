//! The articulation sweep (reference 12, kinematic): move a joint through its range and measure
//! contact with the parent and interpenetration with everything that stays still.

use uniphys_geometry::{Aabb, DVec3, KdTree, principal_axes, projection_range};
use uniphys_types::{Joint, JointKind};

use crate::contact_reference::ContactReference;
use crate::crossing::Crossings;
use crate::fit::{SPIN_RANGE_MIN_RAD, spin_residual};
use crate::handle::{axis_across_panel, handle_on_hinge, is_broad_sheet};
use crate::held::{
    contact_normal_tensor, gap_to_parent_m, hinge_to_parent_m, line_to_points_m, mean,
    rest_contact_m, slide_against_contact, slide_touch_m, touches, touching_samples,
};
use crate::in_plane::{InPlaneTurn, in_plane_turn};
use crate::motion::{JointMotion, sweep_coordinates};
use crate::off_round::{OffRoundSpin, off_round_spin, squat_about};
use crate::part_box::Boxed;
use crate::patch::{PosedTree, grow_patch};
use crate::scene::Scene;
use crate::slide_side::{SlideSide, slide_side};
use crate::slide_trap::{SlideTrap, slide_trap};
use crate::slot::walled_sides;
use crate::sweep_params::SweepParams;
use crate::{VerifyError, VerifyResult};

/// What a sweep measured.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepMetrics {
    /// The kind of the swept joint.
    pub kind: JointKind,
    /// Coordinates visited.
    pub steps: usize,
    /// Contact points with the parent at rest (0: the child does not touch its parent).
    pub initial_contact_points: usize,
    /// Contact threshold found at rest, metres.
    pub contact_threshold_m: f64,
    /// Steps where contact with the parent was found.
    pub contact_steps: usize,
    /// Steps where contact with the parent was lost.
    pub lost_contact_steps: usize,
    /// 95th percentile of the contact thickness ratio (0 without contact steps).
    pub thickness_ratio_p95: f64,
    /// 10th percentile of the contact overlap ratio (1 without contact steps).
    pub overlap_ratio_p10: f64,
    /// Fraction of contact steps whose overlap ratio is bad (1 without contact steps).
    pub bad_overlap_fraction: f64,
    /// Largest interpenetration growth of a moving collider into a still one, metres.
    pub max_penetration_growth_m: f64,
    /// Mean over steps of the penetration growth, metres.
    pub mean_penetration_growth_m: f64,
    /// Steps where the growth exceeded the tolerance.
    pub penetrating_steps: usize,
    /// The penetration tolerance used, metres.
    pub penetration_tolerance_m: f64,
    /// Coordinate of the deepest penetration (rad or m).
    pub worst_coordinate: f64,
    /// Part the moving group penetrated deepest.
    pub worst_part: Option<usize>,
    /// Moving surface samples clear of every other part at rest (the ones crossings count).
    pub clear_points: usize,
    /// Of them, the samples that passed through another part's surface and went beyond it deeper
    /// than `rest_contact_part_fraction` of the group's diagonal, or, where they crossed it
    /// inside the space the moving parts filled at rest, deeper than a short slide's travel.
    pub crossed_points: usize,
    /// `crossed_points / clear_points` at the end of the sweep (0 without clear points).
    pub crossed_fraction: f64,
    /// Of `crossed_fraction`, the share crossed only within a limited joint's end stop (see
    /// `SweepParams::end_stop_travel_fraction`).
    pub end_stop_crossed_fraction: f64,
    /// Coordinate where the share crossed before the end stops first exceeded the maximum (rad
    /// or m), if it did.
    pub crossing_coordinate: Option<f64>,
    /// The part most crossed, if any.
    pub crossed_part: Option<usize>,
    /// Coordinate of the first step that lost contact with the parent, if one did.
    pub lost_contact_coordinate: Option<f64>,
    /// How far the moving samples went below the ground the object stands on (its lowest point
    /// at rest), at the deepest step, metres (0 when they stayed above).
    pub below_ground_m: f64,
    /// The most `below_ground_m` allowed, metres.
    pub below_ground_max_m: f64,
    /// Coordinate of the first step that went deeper below the ground than allowed, if one did.
    pub below_ground_coordinate: Option<f64>,
    /// Turning joints: distance from the axis line (where it passes the moving parts) to the
    /// parent's surface, metres; 0 for slides.
    pub hinge_to_parent_m: f64,
    /// Turning joints: mean distance from the axis line, over the same stretch, to the parent's
    /// surface, metres (small when the hinge runs along its parent); 0 for slides.
    pub hinge_mean_to_parent_m: f64,
    /// Turning joints: the same mean, leaving out open space the line crosses between two
    /// points where it runs through the moving parts (a pin spanning a gap between two holds, as
    /// a bucket's handle's does), metres; 0 for slides.
    pub hinge_pin_to_parent_m: f64,
    /// Turning joints: distance from the axis line to the nearest surface sample of the moving
    /// group, metres; 0 for slides.
    pub hinge_to_part_m: f64,
    /// Turning joints: the largest `hinge_to_part_m` allowed, metres; 0 for slides.
    pub hinge_to_part_max_m: f64,
    /// Turning joints along a panel's edge: how far the panel's handle lies from the axis, a
    /// share of the moving parts' reach from it; `None` without such a handle.
    pub handle_reach_fraction: Option<f64>,
    /// Hinges (revolute) along the plane of a broad sheet (a door, a lid, a screen): the axis
    /// line's mean distance to the parent over the sheet's stretch (`hinge_mean_to_parent_m`)
    /// over the moving group's diagonal; `None` otherwise.
    pub sheet_hinge_off_parent: Option<f64>,
    /// Turning joints along a panel's edge whose handle is a bar: the |cosine| between the bar's
    /// length and the axis (1: along it); `None` without such a bar.
    pub handle_bar_axis_cos: Option<f64>,
    /// Hinges (revolute) along a panel's edge that turn it one way from rest, with a handle: the
    /// cosine between the way the handle first moves and the panel's outer normal (1: pulled
    /// straight out of the face, -1: pushed into it); `None` otherwise.
    pub handle_opening_cos: Option<f64>,
    /// Largest contact threshold a step may need before it counts as contact lost, metres.
    pub contact_reach_m: f64,
    /// Short slides: the largest growth over the sweep of the gap between the moving group and
    /// its parent, metres (0 for other joints).
    pub short_slide_gap_growth_m: f64,
    /// Short slides: the gap growth allowed, metres (0 for other joints).
    pub short_slide_gap_max_m: f64,
    /// Slides: how much the slide presses into (or lifts off) the face it touches at rest
    /// (`a^T T a` over `T`'s largest eigenvalue, see `SweepParams::short_slide_press_min`); 1
    /// for turning joints or without contact normals.
    pub short_slide_press: f64,
    /// Slides: how much walls guide the slide (the smaller eigenvalue of `T` across the axis);
    /// 0 for turning joints or without contact normals.
    pub short_slide_guidance: f64,
    /// Long slides: how many of the four sides across the axis its parent walls in (or any
    /// still part, `SweepParams::slot_walled_by_any_still_part`; a slot, see
    /// `SweepParams::long_slide_walled_sides_min`); 4 for other joints.
    pub long_slide_walled_sides: usize,
    /// Long slides of an object standing on the ground: the vertical component of the unit
    /// direction the part travels (toward the far end of its range; 1 straight up); `None`
    /// otherwise.
    pub long_slide_rise: Option<f64>,
    /// Long slides whose moving part is a broad sheet (a door, a lid, a screen) travelling
    /// along its own plane rather than across it: `true` (then only a slot holds it).
    pub long_slide_along_sheet: bool,
    /// Long slides: the travel (the range's larger end) over the moving parts' own length along
    /// the axis; 0 for other joints.
    pub long_slide_travel_share: f64,
    /// Hinges (revolute) whose axis does not cross the plane of a panel: how many of the four
    /// sides across the axis the parent walls the moving parts in on (a drawer turned about its
    /// depth: its slot); 0 for other joints.
    pub hinge_slot_walled_sides: usize,
    /// Hinges (revolute) whose moving parts are a panel turned about its own normal: how round
    /// it is about the axis and how it is held across its faces; `None` otherwise.
    pub in_plane_turn: Option<InPlaneTurn>,
    /// Continuous joints whose moving parts are round about another line than the joint's
    /// ([`OffRoundSpin`]); `None` otherwise.
    pub off_round_spin: Option<OffRoundSpin>,
    /// Revolute joints limited to less than a half turn whose moving parts are no longer along
    /// the joint's line than across it (a disc or a drum, not a rod or a blade along it): their
    /// roundness residual about that line (`fit::spin_residual`, a share of their diagonal);
    /// `None` otherwise.
    pub part_way_round_residual: Option<f64>,
    /// Continuous joints whose moving parts are a disc or a drum about the joint's line: their
    /// roundness residual about it (as [`Self::part_way_round_residual`]); `None` otherwise.
    /// Round about it, they turn in place.
    pub spin_round_residual: Option<f64>,
    /// Short slides: whether the parent's face surrounds the part and whether the slide takes it
    /// away from its parent ([`SlideSide`]); `None` for other joints or without contact at rest.
    pub short_slide_side: Option<SlideSide>,
    /// Slides: how the parent holds the part from the two ends along the axis ([`SlideTrap`]);
    /// `None` for turning joints or without samples touching the parent off its faces.
    pub slide_trap: Option<SlideTrap>,
}

/// Sweeps `joint` through its limits (continuous joints: one full turn), moving the parts in
/// `moving` (the child and what it carries) while every other part stays at rest.
///
/// Contact (reference 12): the parent's points within a threshold of the moving group; the
/// threshold found at rest may grow by `max_step_increments` per step before the step counts as
/// contact lost. Thickness ratio: spread of a step's contact points across their own
/// least-squares plane over the same spread at rest (at least the step's threshold). Overlap
/// ratio: how much of one contact (at rest or at the step) the other covers, within twice the
/// mean spacing of the initial points.
///
/// Two deviations from the reference, which measures thickness across the initial plane and
/// overlap as the share of a step's points near initial ones: both fail a laptop lid that closes
/// onto its base (the contact grows from the hinge line to the whole face, which is correct);
/// interpenetration, which those metrics stood in for, is measured directly.
///
/// Crossings (the verdict on interpenetration): the moving surface samples clear of every other
/// part at rest are followed outward from rest to each limit; one counts once it passes through
/// another part's own triangles, inside their outline, and goes deeper beyond them than 3 % of
/// the moving group's diagonal (deeper than a short slide's travel where it crossed inside the
/// space the moving samples filled at rest: a button pressed into its face). Open shells and
/// zero-thickness panels are judged as they are, what overlapped at rest is not new, a face
/// sliding flush along another goes through nothing, and a round part turning in place
/// crosses nothing new. A part held along its hinge line keeps its overlap by its contact at
/// that line. Collider penetration (a measure for the grounder, not a verdict): for each pair
/// of a moving and a still convex collider, the contact depth (parry, GJK/EPA) minus its depth
/// at rest.
///
/// Measured at rest, for the physical sense of the joint: a turning axis's distance from the
/// moving parts (a hinge is held by its part), where a panel's handle lies from a hinge along its
/// edge ([`crate::panel_handle`]), how a short slide meets the surface it touches (pressing
/// into a face or guided by walls, from the parent's triangle normals there) and which way it
/// goes (a button into the face around it, a lid off the parent it caps: [`SlideSide`]).
///
/// Errors: a fixed joint, a joint without limits (other than continuous), parts out of range.
pub fn sweep(
    scene: &Scene,
    joint: &Joint,
    moving: &[usize],
    params: &SweepParams,
) -> VerifyResult<SweepMetrics> {
    let n = scene.part_count();
    let parent = joint.parent.0 as usize;
    for part in std::iter::once(parent).chain(moving.iter().copied()) {
        if part >= n {
            return Err(VerifyError::MissingPart {
                joint: joint.name.clone(),
                part: uniphys_types::PartId(part as u32),
            });
        }
    }
    let (lower, upper) = match (joint.kind, joint.limits) {
        (JointKind::Continuous, _) => (-std::f64::consts::PI, std::f64::consts::PI),
        (JointKind::Fixed, _) => {
            return Err(VerifyError::InvalidParameter(format!(
                "joint {:?} is fixed: nothing to sweep",
                joint.name
            )));
        }
        (_, Some(l)) => (l.lower, l.upper),
        (_, None) => {
            return Err(VerifyError::InvalidParameter(format!(
                "joint {:?} has no limits to sweep",
                joint.name
            )));
        }
    };
    let diag = scene.diagonal_m;
    let motion = JointMotion::of(joint);
    let moving_points = scene.points_of(moving);
    let parent_points = &scene.samples[parent];
    let still = scene.still_parts(moving);
    let colliders = &scene.colliders;
    let moving_hulls = colliders.of_parts(moving);
    let still_hulls = colliders.of_parts(&still);
    let rest_pose = colliders.posed(&motion, 0.0, &moving_hulls);
    // Only pairs that can meet anywhere in the range (and at rest) are queried.
    let pairs: Vec<(usize, usize)> = moving_hulls
        .iter()
        .flat_map(|&a| still_hulls.iter().map(move |&b| (a, b)))
        .filter(|&(a, b)| colliders.may_meet(a, b, &motion, lower.min(0.0), upper.max(0.0)))
        .collect();
    let baseline: Vec<f64> = pairs
        .iter()
        .map(|&(a, b)| colliders.depth_m(a, &rest_pose, b))
        .collect();
    let patch = &params.patch;
    let start = patch.start_fraction * diag;
    let step = patch.step_fraction * diag;
    let moving_tree = KdTree::new(moving_points.clone());
    let initial = grow_patch(
        parent_points,
        &moving_tree,
        start,
        step,
        patch.initial_increments(),
        patch.min_points,
    );
    let reference = match &initial {
        Some((points, threshold)) => Some(ContactReference::new(
            points,
            *threshold,
            &motion,
            &moving_tree,
            &moving_points,
            parent_points,
            (start, step, patch.initial_increments()),
        )?),
        None => None,
    };

    let tolerance = params.penetration_tolerance_fraction * diag;
    let moving_diagonal_m = Aabb::from_points(&moving_points).diagonal();
    let hinge = hinge_to_parent_m(
        scene,
        &motion,
        (moving, &moving_points, moving_diagonal_m),
        parent,
    );
    let (hinge_to_part_m, hinge_to_part_max_m) = if motion.kind == JointKind::Prismatic {
        (0.0, 0.0)
    } else {
        (
            line_to_points_m(&motion, &moving_points),
            params.hinge_off_part_fraction * moving_diagonal_m,
        )
    };
    let mut metrics = SweepMetrics {
        kind: joint.kind,
        steps: params.steps,
        initial_contact_points: initial.as_ref().map_or(0, |(p, _)| p.len()),
        contact_threshold_m: initial.as_ref().map_or(0.0, |(_, t)| *t),
        contact_steps: 0,
        lost_contact_steps: 0,
        thickness_ratio_p95: 0.0,
        overlap_ratio_p10: 1.0,
        bad_overlap_fraction: 1.0,
        max_penetration_growth_m: 0.0,
        mean_penetration_growth_m: 0.0,
        penetrating_steps: 0,
        penetration_tolerance_m: tolerance,
        worst_coordinate: 0.0,
        worst_part: None,
        clear_points: 0,
        crossed_points: 0,
        crossed_fraction: 0.0,
        end_stop_crossed_fraction: 0.0,
        crossing_coordinate: None,
        crossed_part: None,
        lost_contact_coordinate: None,
        below_ground_m: 0.0,
        below_ground_max_m: params.below_ground_fraction_max * diag,
        below_ground_coordinate: None,
        hinge_to_parent_m: hinge.min_m,
        hinge_mean_to_parent_m: hinge.mean_m,
        hinge_pin_to_parent_m: hinge.pin_mean_m,
        hinge_to_part_m,
        hinge_to_part_max_m,
        handle_reach_fraction: None,
        handle_bar_axis_cos: None,
        handle_opening_cos: None,
        sheet_hinge_off_parent: None,
        contact_reach_m: initial.as_ref().map_or(0.0, |(_, t)| *t)
            + step * patch.max_step_increments as f64,
        short_slide_gap_growth_m: 0.0,
        short_slide_gap_max_m: 0.0,
        short_slide_press: 1.0,
        short_slide_guidance: 0.0,
        long_slide_walled_sides: 4,
        long_slide_rise: None,
        long_slide_along_sheet: false,
        long_slide_travel_share: 0.0,
        hinge_slot_walled_sides: 0,
        in_plane_turn: None,
        off_round_spin: None,
        part_way_round_residual: None,
        spin_round_residual: None,
        short_slide_side: None,
        slide_trap: None,
    };
    // A short slide (a button, a cap's lift) must stay at its parent: its gap to the parent is
    // followed against the one at rest.
    let short_slide = (joint.kind == JointKind::Prismatic).then(|| {
        let span = |points: &[DVec3]| Aabb::from_points(points).diagonal();
        let travel = lower.abs().max(upper.abs());
        (travel <= params.short_slide_fraction * span(parent_points))
            .then(|| params.short_slide_gap_fraction * span(&moving_points))
    });
    let gap_at_rest = match short_slide {
        Some(Some(_)) => gap_to_parent_m(scene, parent, &moving_points),
        _ => 0.0,
    };
    metrics.short_slide_gap_max_m = short_slide.flatten().unwrap_or(0.0);
    // The moving group's box and its part's (the same when it carries nothing), found once for
    // the rules below.
    let moving_boxed = Boxed::of_parts(&moving_points, scene, moving);
    let child_points = &scene.samples[joint.child.0 as usize];
    let child_part = [joint.child.0 as usize];
    let child_own;
    let child_boxed = if moving == child_part {
        &moving_boxed
    } else {
        child_own = Boxed::of_parts(child_points, scene, &child_part);
        &child_own
    };
    // A broad sheet held along an edge (its contact at rest runs along most of it) hangs on
    // that edge; one held by a small patch (a spout on its collar) turns on the patch.
    let held_along_edge = || {
        initial.as_ref().is_some_and(|(contact, _)| {
            let [longest, ..] = principal_axes(contact);
            let (lo, hi) = projection_range(contact, longest);
            hi - lo >= params.sheet_contact_fraction_min * child_boxed.part_box().diagonal
        })
    };
    if joint.kind == JointKind::Revolute
        && moving_diagonal_m > 0.0
        && is_broad_sheet(
            child_boxed.part_box(),
            scene.area_m2(joint.child.0 as usize),
        )
        && !axis_across_panel(child_boxed.part_box(), motion.axis_in_object)
        && held_along_edge()
    {
        metrics.sheet_hinge_off_parent = Some(hinge.mean_m / moving_diagonal_m);
    }
    // A spin (continuous) is judged by its roundness where it is chosen and corrected (`fit`):
    // a grounder's spin line through a knob with a pointer is rounder than a hinge's but not
    // exactly on the knob's own axis.
    if joint.kind == JointKind::Revolute {
        metrics.in_plane_turn = in_plane_turn(
            scene,
            &moving_boxed,
            &still,
            motion.axis_in_object,
            motion.pivot_in_object_m,
            rest_contact_m(params, moving_diagonal_m, diag),
        );
    }
    if joint.kind == JointKind::Revolute
        && joint
            .limits
            .is_some_and(|l| l.upper - l.lower < SPIN_RANGE_MIN_RAD)
        && squat_about(
            &moving_points,
            motion.pivot_in_object_m,
            motion.axis_in_object,
        )
    {
        metrics.part_way_round_residual = Some(spin_residual(
            &moving_points,
            motion.axis_in_object,
            motion.pivot_in_object_m,
        ));
    }
    if joint.kind == JointKind::Continuous {
        let residual = spin_residual(
            &moving_points,
            motion.axis_in_object,
            motion.pivot_in_object_m,
        );
        metrics.spin_round_residual = squat_about(
            &moving_points,
            motion.pivot_in_object_m,
            motion.axis_in_object,
        )
        .then_some(residual);
        metrics.off_round_spin = off_round_spin(
            scene,
            moving,
            &moving_points,
            motion.axis_in_object,
            residual,
            params.off_round_residual_min,
        );
    }
    if joint.kind != JointKind::Prismatic {
        let away = mean(&moving_points) - mean(parent_points);
        let handle = handle_on_hinge(
            child_boxed,
            &moving_boxed,
            parent_points,
            motion.axis_in_object,
            motion.pivot_in_object_m,
            away,
        );
        metrics.handle_reach_fraction = handle.map(|h| h.reach_fraction);
        metrics.handle_bar_axis_cos = handle.and_then(|h| h.bar_axis_cos);
        // A hinge turning its part one way from rest: how its handle first moves.
        let way = match joint.kind {
            JointKind::Revolute if lower >= 0.0 && upper > 0.0 => Some(1.0),
            JointKind::Revolute if upper <= 0.0 && lower < 0.0 => Some(-1.0),
            _ => None,
        };
        metrics.handle_opening_cos = handle.zip(way).and_then(|(h, way)| {
            h.opening_cos(motion.axis_in_object, motion.pivot_in_object_m, way)
        });
    }
    // A long slide (a slide that is not short) must run in a slot of its parent (of anything
    // still, for parts a decomposition cut).
    if short_slide == Some(None) {
        let walls: &[usize] = if params.slot_walled_by_any_still_part {
            &still
        } else {
            &[parent]
        };
        metrics.long_slide_walled_sides =
            walled_sides(scene, walls, &moving_points, motion.axis_in_object);
        // ... and stays in it: a drawer travels less than its depth.
        let (lo, hi) = projection_range(&moving_points, motion.axis_in_object.normalize_or_zero());
        metrics.long_slide_travel_share = upper.abs().max(lower.abs()) / (hi - lo).max(1e-12);
        // A lid lifts off its pot across its own plane; a door slid along its cabinet's face is
        // held by nothing but a slot, whatever ledge it rests on.
        metrics.long_slide_along_sheet =
            is_broad_sheet(
                child_boxed.part_box(),
                scene.area_m2(joint.child.0 as usize),
            ) && !axis_across_panel(child_boxed.part_box(), motion.axis_in_object);
        if scene.ground_z_m.is_some() {
            let outward = if upper.abs() >= lower.abs() {
                1.0
            } else {
                -1.0
            };
            metrics.long_slide_rise = Some(outward * motion.axis_in_object.normalize_or_zero().z);
        }
    }
    // A hinge must not turn a part about the axis of the slot it sits in (a drawer about its
    // depth); a panel turned about its own normal is judged in the plane it turns in.
    if joint.kind == JointKind::Revolute
        && !axis_across_panel(moving_boxed.part_box(), motion.axis_in_object)
    {
        metrics.hinge_slot_walled_sides =
            walled_sides(scene, &[parent], &moving_points, motion.axis_in_object);
    }
    if joint.kind == JointKind::Prismatic {
        let touch_m = slide_touch_m(params, &moving_points);
        let at_parent = touches(scene, parent, &moving_points, touch_m);
        if let Some(tensor) = contact_normal_tensor(&at_parent) {
            (metrics.short_slide_press, metrics.short_slide_guidance) =
                slide_against_contact(tensor, motion.axis_in_object);
        }
        metrics.slide_trap = slide_trap(&at_parent, &moving_points, touch_m, motion.axis_in_object);
        if matches!(short_slide, Some(Some(_))) {
            metrics.short_slide_side = slide_side(
                scene,
                parent,
                &moving_points,
                &touching_samples(scene, parent, &moving_points, touch_m),
                motion.axis_in_object,
                (lower, upper),
            );
        }
    }
    let mut crossings = Crossings::new(
        scene,
        &moving_points,
        moving,
        &still,
        &motion,
        (lower.min(0.0), upper.max(0.0)),
        params,
    );
    metrics.clear_points = crossings.clear.len();
    let mut thickness = Vec::new();
    let mut overlap = Vec::new();
    let mut growth_sum = 0.0;
    // Visited outward from the rest pose, the positive side first: every point's path is then
    // continuous from rest (a continuous joint's first step is not a jump to half a turn).
    let coordinates = sweep_coordinates(lower, upper, params.steps);
    let limited = matches!(joint.kind, JointKind::Revolute | JointKind::Prismatic);
    let in_end_stop = |q: f64| {
        let side = if q >= 0.0 { upper } else { lower };
        limited && side != 0.0 && q / side >= 1.0 - params.end_stop_travel_fraction
    };
    let mut end_stop_crossed = 0usize;
    let clear_count = crossings.clear.len() as f64;
    let mut order: Vec<f64> = coordinates.iter().copied().filter(|&q| q >= 0.0).collect();
    order.extend(coordinates.iter().rev().copied().filter(|&q| q < 0.0));
    let mut previous_side = true;
    for q in order {
        if previous_side != (q >= 0.0) {
            previous_side = q >= 0.0;
            crossings.restart(&moving_points);
        }
        let pose = colliders.posed(&motion, q, &moving_hulls);
        let mut deepest = (0.0f64, None);
        for (&(a, b), rest) in pairs.iter().zip(&baseline) {
            let growth = colliders.depth_m(a, &pose, b) - rest;
            if growth > deepest.0 {
                deepest = (growth, Some(colliders.hulls[b].part));
            }
        }
        growth_sum += deepest.0;
        if deepest.0 > tolerance {
            metrics.penetrating_steps += 1;
        }
        if deepest.0 > metrics.max_penetration_growth_m {
            metrics.max_penetration_growth_m = deepest.0;
            metrics.worst_coordinate = q;
            metrics.worst_part = deepest.1;
        }
        let to_object = motion.object_from_moved(q);
        let moved: Vec<DVec3> = moving_points
            .iter()
            .map(|p| to_object.transform_point3(*p))
            .collect();
        let crossed_before = crossings.crossed_count;
        crossings.advance(scene, &moved);
        if in_end_stop(q) {
            end_stop_crossed += crossings.crossed_count - crossed_before;
        }
        if let Some(ground_z_m) = scene.ground_z_m {
            let lowest_z_m = moved.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
            metrics.below_ground_m = metrics.below_ground_m.max(ground_z_m - lowest_z_m);
        }
        if metrics.below_ground_coordinate.is_none()
            && metrics.below_ground_m > metrics.below_ground_max_m
        {
            metrics.below_ground_coordinate = Some(q);
        }
        let before_end_stops = crossings.crossed_count - end_stop_crossed;
        if metrics.crossing_coordinate.is_none()
            && before_end_stops as f64 > params.crossing_fraction_max * clear_count
        {
            metrics.crossing_coordinate = Some(q);
        }
        if metrics.short_slide_gap_max_m > 0.0 {
            let growth = gap_to_parent_m(scene, parent, &moved) - gap_at_rest;
            metrics.short_slide_gap_growth_m = metrics.short_slide_gap_growth_m.max(growth);
        }
        let moved_tree = PosedTree::new(&moving_tree, to_object);
        if let Some(reference) = &reference {
            let found = moved_tree.grow_patch(
                parent_points,
                reference.threshold_m,
                step,
                patch.max_step_increments,
                patch.min_points,
            );
            match found {
                Some((points, threshold)) => {
                    metrics.contact_steps += 1;
                    thickness.push(reference.thickness_ratio(&points, threshold)?);
                    overlap.push(reference.overlap_ratio(&points, &moved_tree));
                }
                None => {
                    metrics.lost_contact_steps += 1;
                    metrics.lost_contact_coordinate.get_or_insert(q);
                }
            }
        }
    }
    metrics.mean_penetration_growth_m = growth_sum / params.steps.max(1) as f64;
    metrics.crossed_points = crossings.crossed_count;
    metrics.crossed_fraction = crossings.fraction();
    if clear_count > 0.0 {
        metrics.end_stop_crossed_fraction = end_stop_crossed as f64 / clear_count;
    }
    metrics.crossed_part = crossings.most_crossed();
    if !thickness.is_empty() {
        metrics.thickness_ratio_p95 = percentile(&mut thickness, 95.0);
        metrics.bad_overlap_fraction = overlap.iter().filter(|&&o| o < params.overlap_min).count()
            as f64
            / overlap.len() as f64;
        metrics.overlap_ratio_p10 = percentile(&mut overlap, 10.0);
    }
    Ok(metrics)
}

/// Percentile with linear interpolation between closest ranks (numpy's default).
fn percentile(values: &mut [f64], pct: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let rank = pct / 100.0 * (values.len() - 1) as f64;
    let (lo, hi) = (rank.floor() as usize, rank.ceil() as usize);
    values[lo] + (values[hi] - values[lo]) * (rank - lo as f64)
}
