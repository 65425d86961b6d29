//! The variants of a failed joint that its correction (`correct`) tries, tier by tier: its range
//! reversed or cut; for a knob pulled off its face, a spin about its line; for a round part turned
//! part-way, a press or a spin about that line; other pivots, other axes, the other kind of
//! motion. Each variant names what it changed, for the report.

use uniphys_geometry::{DVec3, box_axes, projection_range, symmetric_eigen};
use uniphys_types::{Joint, JointKind, JointLimits};

use crate::candidates::{articulation_candidates, band_pivots, distinct_lines, edge_pivots};
use crate::fit::{may_spin, round_axis, spin_residual};
use crate::held::{contact_normal_tensor, mean, slide_touch_m, touches};
use crate::in_plane::held_pivots;
use crate::part_box::PartBox;
use crate::round_axis::{RoundAxis, centre_about, push_travel_m};
use crate::rounded_ends::rounded_end_pivots;
use crate::scene::Scene;
use crate::sweep::SweepMetrics;
use crate::sweep_params::SweepParams;

/// A failure at or beyond this fraction of the way to the limit on its side comes late.
const LATE_FAILURE_FRACTION: f64 = 0.75;
/// Slide travel tried when a turn becomes a slide, as fractions of the part's extent along the
/// axis (largest first: the range is as far as the part can go).
const SLIDE_TRAVEL_FRACTIONS: [f64; 3] = [0.8, 0.5, 0.25];

/// Presses tried for a round button turned part-way, as fractions of the grounder's stroke
/// ([`push_travel_m`]): the whole stroke, and half of it for a button whose half depth already
/// reaches into the face behind it.
const PRESS_STROKE_FRACTIONS: [f64; 2] = [1.0, 0.5];

/// One way of changing a joint.
pub(crate) struct Variant {
    /// The changed joint.
    pub(crate) joint: Joint,
    /// What was changed, for the report.
    pub(crate) change: String,
}

/// `joint` with another kind, axis, pivot and range.
fn changed(
    joint: &Joint,
    kind: JointKind,
    axis: DVec3,
    pivot: DVec3,
    limits: Option<JointLimits>,
) -> Joint {
    let mut j = joint.clone();
    j.kind = kind;
    j.axis_in_object = axis.to_array();
    j.pivot_in_object_m = pivot.to_array();
    j.limits = limits;
    j
}

/// The range `[lower, upper]`.
fn range(lower: f64, upper: f64) -> Option<JointLimits> {
    Some(JointLimits { lower, upper })
}

/// A range run the other way.
pub(crate) fn reversed(limits: Option<JointLimits>) -> Option<JointLimits> {
    limits.map(|l| JointLimits {
        lower: -l.upper,
        upper: -l.lower,
    })
}

/// The variants of `joint` that change only its range (tiers 1 and 2).
pub(crate) fn range_tiers(joint: &Joint, original: &SweepMetrics) -> Vec<Vec<Variant>> {
    let axis = DVec3::from_array(joint.axis_in_object).normalize_or_zero();
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    let limits = joint.limits;
    let with = |kind, a, p, limits| changed(joint, kind, a, p, limits);

    // 1-2. The other way, and as far as the sweep went before it failed: the cut first when the
    // failure comes late (the part closes onto something past a limit that overshoots), the
    // reversal first when it comes early (the part moves into its parent at once).
    let mut reverse_tier = Vec::new();
    if let Some(r) = reversed(limits) {
        reverse_tier.push(Variant {
            joint: with(joint.kind, axis, pivot, Some(r)),
            change: format!("range reversed to [{:.4}, {:.4}]", r.lower, r.upper),
        });
    }
    let mut cut_tier = Vec::new();
    let mut late = false;
    if let (Some(l), Some(q)) = (limits, original.failure_coordinate()) {
        let end = if q > 0.0 { l.upper } else { l.lower };
        late = end != 0.0 && q / end >= LATE_FAILURE_FRACTION;
        let cut = if q > 0.0 {
            (l.lower, l.lower.max(0.0) + 0.9 * (q - l.lower.max(0.0)))
        } else {
            (l.upper.min(0.0) + 0.9 * (q - l.upper.min(0.0)), l.upper)
        };
        if cut.1 - cut.0 > 0.25 * (l.upper - l.lower) {
            cut_tier.push(Variant {
                joint: with(joint.kind, axis, pivot, range(cut.0, cut.1)),
                change: format!(
                    "range cut to [{:.4}, {:.4}] where the sweep first failed",
                    cut.0, cut.1
                ),
            });
        }
    }
    if late {
        vec![cut_tier, reverse_tier]
    } else {
        vec![reverse_tier, cut_tier]
    }
}

/// The variants of `joint` after its range (tiers 3 on): built only when no range change ended
/// the search, since they need the articulation candidates of its contact.
pub(crate) fn change_tiers(
    scene: &Scene,
    joint: &Joint,
    moving: &[usize],
    params: &SweepParams,
    nearly_passed: bool,
) -> Vec<Vec<Variant>> {
    let axis = DVec3::from_array(joint.axis_in_object).normalize_or_zero();
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    let child_points = scene.points_of(&[joint.child.0 as usize]);
    let part_axes = box_axes(&child_points);
    let limits = joint.limits;
    let reversed = reversed(limits);
    let with = |kind, a, p, limits| changed(joint, kind, a, p, limits);
    let mut tiers: Vec<Vec<Variant>> = Vec::new();
    let moving_points = scene.points_of(moving);
    let parent_points = scene.points_of(&[joint.parent.0 as usize]);
    let candidates = articulation_candidates(
        &moving_points,
        &parent_points,
        part_axes,
        scene.diagonal_m,
        &params.patch,
        params.seed,
    )
    .ok();
    let mut pivots: Vec<DVec3> = candidates
        .as_ref()
        .map_or_else(Vec::new, |c| c.pivots.clone());
    pivots.extend(edge_pivots(&child_points, &parent_points, part_axes));
    if joint.kind != JointKind::Prismatic {
        pivots.extend(band_pivots(&moving_points, axis, part_axes));
        pivots.extend(rounded_end_pivots(&moving_points, axis, part_axes));
        pivots.extend(held_pivots(scene, moving, axis, params));
    }

    // 3. A part that spins in place: the line it is round about, both ways.
    if !nearly_passed
        && may_spin(joint)
        && let Some((a, p, residual)) = round_axis(
            &moving_points,
            &[axis, part_axes[0], part_axes[1], part_axes[2]],
        )
        && (line_angle(a, axis) > 1e-3
            || (p - pivot).reject_from_normalized(a).length() > 1e-3 * scene.diagonal_m)
    {
        tiers.push(
            [a, -a]
                .into_iter()
                .map(|a| Variant {
                    joint: with(joint.kind, a, p, limits),
                    change: format!(
                        "turned about the line it is round about, axis ({:.3}, {:.3}, {:.3}) through ({:.4}, {:.4}, {:.4}) (residual {residual:.3})",
                        a.x, a.y, a.z, p.x, p.y, p.z
                    ),
                })
                .collect(),
        );
    }
    // 4. Another pivot on the same axis: the same way first, then reversed.
    if joint.kind != JointKind::Prismatic {
        let moved: Vec<DVec3> = distinct_lines(&pivots, axis, 1e-3 * scene.diagonal_m)
            .into_iter()
            .filter(|p| {
                (*p - pivot).reject_from_normalized(axis).length() > 1e-3 * scene.diagonal_m
            })
            .collect();
        for (lim, how) in [(limits, ""), (reversed, ", range reversed")] {
            tiers.push(
                moved
                    .iter()
                    .map(|p| Variant {
                        joint: with(joint.kind, axis, *p, lim),
                        change: format!("pivot moved to ({:.4}, {:.4}, {:.4}){how}", p.x, p.y, p.z),
                    })
                    .collect(),
            );
        }
    }
    // A joint that nearly passed keeps its axis.
    if nearly_passed {
        return tiers;
    }
    // 5. Another axis, both ways: for a slide first the normal of the face it touches and the
    // axis of walls around it (a press, a guided slide), then the square directions near the
    // candidates, then the candidates from the contact and the part's box.
    let contact_axes: Vec<DVec3> = if joint.kind == JointKind::Prismatic {
        let touch_m = slide_touch_m(params, &moving_points);
        contact_normal_tensor(&touches(
            scene,
            joint.parent.0 as usize,
            &moving_points,
            touch_m,
        ))
        .map(|tensor| {
            let (_, vectors) = symmetric_eigen(tensor);
            vec![vectors.z_axis, vectors.x_axis]
        })
        .unwrap_or_default()
    } else {
        Vec::new()
    };
    // The part's own box axes first: a contact axis a few degrees off one of them is the same
    // hinge or spin, and the part's edge or symmetry gives it more exactly.
    let mut axes: Vec<DVec3> = part_axes.to_vec();
    axes.extend(candidates.as_ref().map_or(&[][..], |c| &c.axes[..]));
    let square = square_axes(scene, &parent_points, &axes);
    tiers.push(axis_variants(&contact_axes, &[], axis, |a| {
        with(joint.kind, a, pivot, limits)
    }));
    tiers.push(axis_variants(&square, &contact_axes, axis, |a| {
        with(joint.kind, a, pivot, limits)
    }));
    let tried: Vec<DVec3> = contact_axes.iter().chain(&square).copied().collect();
    tiers.push(axis_variants(&axes, &tried, axis, |a| {
        with(joint.kind, a, pivot, limits)
    }));
    // A panel its parent holds on both faces (a folding knife's blade between its scales) turns
    // about its own normal on the pin through the held region, which the axis alone, kept
    // through the old pivot, misses.
    if joint.kind != JointKind::Prismatic {
        // The joint's own axis had these pivots in tier 4.
        let mut tier = Vec::new();
        for normal in part_axes
            .into_iter()
            .filter(|a| line_angle(*a, axis) >= AXIS_MERGE_RAD)
        {
            for p in held_pivots(scene, moving, normal, params) {
                for a in [normal, -normal] {
                    tier.push(Variant {
                        joint: with(joint.kind, a, p, limits),
                        change: format!(
                            "turned about the panel's normal ({:.3}, {:.3}, {:.3}) on the pin its parent holds, through ({:.4}, {:.4}, {:.4})",
                            a.x, a.y, a.z, p.x, p.y, p.z
                        ),
                    });
                }
            }
        }
        tiers.push(tier);
    }

    // 6. The other kind of motion along or about the same axis.
    let mut tier = Vec::new();
    match joint.kind {
        JointKind::Revolute | JointKind::Continuous => {
            tier.extend(slide_tier(joint, &child_points, axis, pivot));
        }
        JointKind::Prismatic => {
            let quarter = std::f64::consts::FRAC_PI_2;
            for p in distinct_lines(&pivots, axis, 1e-3 * scene.diagonal_m) {
                for (l, h) in [(0.0, quarter), (-quarter, 0.0)] {
                    tier.push(Variant {
                        joint: with(JointKind::Revolute, axis, p, range(l, h)),
                        change: format!(
                            "made a hinge about the axis through ({:.4}, {:.4}, {:.4}), range [{l:.4}, {h:.4}]",
                            p.x, p.y, p.z
                        ),
                    });
                }
            }
        }
        JointKind::Fixed => {}
    }
    tiers.push(tier);
    tiers
}

/// The variants of a revolute `joint` that turns a part round about its line part-way, a tier
/// each, both kept on that line. A round knob and a round button sitting on a panel look alike
/// to a sweep (each can be pushed a few millimetres into it), so the part's shape decides, as it
/// does for the grounder ([`RoundAxis::pressed`]): a small part, squat and smooth all round on a
/// face of its parent, which a hand has nothing to turn by, is a button, pressed into its parent
/// as the grounder presses one ([`push_travel_m`]), then spun if that fails; any other (a knob
/// with a grip, a cap, a lid) is spun, then slid along the line both ways if that fails.
pub(crate) fn round_part_tiers(scene: &Scene, joint: &Joint) -> Vec<Vec<Variant>> {
    let axis = DVec3::from_array(joint.axis_in_object).normalize_or_zero();
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    let spin = vec![Variant {
        joint: changed(joint, JointKind::Continuous, axis, pivot, None),
        change: "made a spin about the same line".to_owned(),
    }];
    let child_points = scene.points_of(&[joint.child.0 as usize]);
    let middle = centre_about(&child_points, axis);
    let (round, pressed) = child_about_line(scene, joint, &child_points, axis, middle);
    if !pressed {
        return vec![spin, slide_tier(joint, &child_points, axis, pivot)];
    }
    let (lo, hi) = projection_range(&child_points, axis);
    let stroke = push_travel_m(hi - lo, round.width_m);
    let inward = (mean(&scene.samples[joint.parent.0 as usize]) - mean(&child_points)).dot(axis);
    let press = PRESS_STROKE_FRACTIONS
        .iter()
        .map(|fraction| {
            let travel = fraction * stroke;
            let limits = if inward >= 0.0 {
                range(0.0, travel)
            } else {
                range(-travel, 0.0)
            };
            Variant {
                joint: changed(joint, JointKind::Prismatic, axis, pivot, limits),
                change: format!("made a press along the same line into its parent, {travel:.4} m"),
            }
        })
        .collect();
    vec![press, spin]
}

/// A slide (`joint`) that pulled its part off the broad face it stands on
/// ([`SweepMetrics::pulled_off_broad_face`], its sweep `original`) moved a knob or a button
/// along its own line. A part round about that line with a grip (a knob: not
/// [`RoundAxis::pressed`], as the grounder reads it) is spun about it, a tier before the range
/// tiers; a button, or a part round about no line, is left to them (reversed, it is pressed in).
pub(crate) fn knob_spin_tiers(
    scene: &Scene,
    joint: &Joint,
    original: &SweepMetrics,
    params: &SweepParams,
) -> Vec<Vec<Variant>> {
    if joint.kind != JointKind::Prismatic || !original.pulled_off_broad_face(params) {
        return Vec::new();
    }
    let axis = DVec3::from_array(joint.axis_in_object).normalize_or_zero();
    let child_points = scene.points_of(&[joint.child.0 as usize]);
    let centre = centre_about(&child_points, axis);
    if spin_residual(&child_points, axis, centre) > params.part_way_round_residual_max
        || child_about_line(scene, joint, &child_points, axis, centre).1
    {
        return Vec::new();
    }
    vec![vec![Variant {
        joint: changed(joint, JointKind::Continuous, axis, centre, None),
        change: format!(
            "made a spin about its own line through ({:.4}, {:.4}, {:.4}): a knob pulled off the face it stands on",
            centre.x, centre.y, centre.z
        ),
    }]]
}

/// The shape of `joint`'s child (sampled at `child_points`) about the line along `axis` through
/// `through`, and whether a hand would press it rather than turn it ([`RoundAxis::pressed`], the
/// grounder's test).
fn child_about_line(
    scene: &Scene,
    joint: &Joint,
    child_points: &[DVec3],
    axis: DVec3,
    through: DVec3,
) -> (RoundAxis, bool) {
    let child = joint.child.0 as usize;
    let diagonal_m = PartBox::of(child_points).diagonal;
    let round = RoundAxis::about_line(scene, child, child_points, diagonal_m, axis, through);
    let pressed = round.pressed(scene, joint.parent.0 as usize, child_points, diagonal_m);
    (round, pressed)
}

/// A turning `joint` made a slide along `axis`, both ways, over [`SLIDE_TRAVEL_FRACTIONS`] of
/// its part's extent along it (sampled at `child_points`; largest first).
fn slide_tier(joint: &Joint, child_points: &[DVec3], axis: DVec3, pivot: DVec3) -> Vec<Variant> {
    let (lo, hi) = projection_range(child_points, axis);
    let mut tier = Vec::new();
    for fraction in SLIDE_TRAVEL_FRACTIONS {
        let travel = fraction * (hi - lo);
        // A part drawn without thickness along the axis gives no travel to read.
        if travel <= f64::EPSILON * (hi.abs() + lo.abs()).max(1.0) {
            continue;
        }
        for (l, h) in [(0.0, travel), (-travel, 0.0)] {
            tier.push(Variant {
                joint: changed(joint, JointKind::Prismatic, axis, pivot, range(l, h)),
                change: format!("made a slide along the axis, range [{l:.4}, {h:.4}]"),
            });
        }
    }
    tier
}

/// Variants of a joint (`make` gives it for an axis) along each of `axes`, both ways, that
/// differ from `axis` and from each other and from every one of `tried` by more than
/// [`AXIS_MERGE_RAD`] (the first of a closer pair is kept).
fn axis_variants(
    axes: &[DVec3],
    tried: &[DVec3],
    axis: DVec3,
    make: impl Fn(DVec3) -> Joint,
) -> Vec<Variant> {
    let mut distinct: Vec<DVec3> = Vec::new();
    for a in axes {
        let a = a.normalize_or_zero();
        if a == DVec3::ZERO || line_angle(a, axis) < AXIS_MERGE_RAD {
            continue;
        }
        if distinct
            .iter()
            .chain(tried)
            .all(|b| line_angle(a, *b) > AXIS_MERGE_RAD)
        {
            distinct.push(a);
        }
    }
    let mut out = Vec::new();
    for a in &distinct {
        for sign in [1.0, -1.0] {
            let a = *a * sign;
            out.push(Variant {
                joint: make(a),
                change: format!("axis changed to ({:.3}, {:.3}, {:.3})", a.x, a.y, a.z),
            });
        }
    }
    out
}

/// The directions a mechanism is built square to that lie within [`SQUARE_SNAP_RAD`] of one of
/// `axes`: the vertical, when the object stands on the ground, and the axes of the parent's box
/// (sampled at `parent_points`). An axis found from a part's box or its contact is a few
/// degrees off the hinge or spin it stands for (a lever's box tilted by its grip, a contact
/// patch's rim); the square direction near it is tried first.
fn square_axes(scene: &Scene, parent_points: &[DVec3], axes: &[DVec3]) -> Vec<DVec3> {
    let mut square: Vec<DVec3> = Vec::new();
    if scene.ground_z_m.is_some() {
        square.push(DVec3::Z);
    }
    square.extend(box_axes(parent_points));
    square
        .into_iter()
        .filter(|s| axes.iter().any(|a| line_angle(*s, *a) < SQUARE_SNAP_RAD))
        .collect()
}

/// An axis candidate within this angle of a square direction ([`square_axes`]) is tried along
/// that direction first, radians (15 degrees).
pub(crate) const SQUARE_SNAP_RAD: f64 = 0.26;

/// Axes closer than this are one candidate, radians (a part's edge and a hinge line from its
/// contact differ by a few degrees on real objects).
const AXIS_MERGE_RAD: f64 = 0.1;

/// Angle between two lines (sign ignored), radians.
pub(crate) fn line_angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .abs()
        .clamp(0.0, 1.0)
        .acos()
}
