//! Feedback correction of a joint that failed its sweep, in tiers of growing change: for a slide
//! that pulled a round part with a grip off the broad face it stands on (a knob), a spin about its
//! own line first; the range reversed or cut where the sweep first failed; for a part that spins in
//! place, the line it is round about; another pivot on the same axis (contact clusters, the part's
//! edge lines, its edges' cross-sections, the centres of its rounded ends and, for a panel its
//! parent holds on both faces, of the held region), keeping the direction, then reversing it;
//! another axis (for a slide first the normal of the face it touches and the axis of the walls
//! around it; then the directions a mechanism is built square to near the candidates: the vertical
//! of an object on the ground, the parent's box axes; for a panel its parent holds on both faces,
//! its normal through the held pin); the other kind of motion (slide for turn, turn for slide).
//!
//! Within a tier the passing variant that fits the parts best wins (`fit::misfit`: a hinge along
//! its parent and across from the handle, a spin about the part's own round axis, a slide that
//! stays on its parent; a range cut counts against it by the share cut away), then the one with the
//! most margin; a variant listed before it that moves the same way about a line a few degrees off
//! (a part's box axis before a contact axis near it) wins instead when it fits nearly as well.
//! Across tiers the smaller change wins unless a later tier's fits the parts clearly better and is
//! of the same kind of motion (a turn or a slide), or is a turn replacing a slide that left its
//! parent or runs askew (a laptop's screen slid off its base, a door slid diagonally across its
//! cabinet's face); a correction that fits well ends the search. A joint that nearly passed keeps
//! its axis: its range changes, or, when that fits the parts poorly (a door reversed about its
//! handle's edge), its pivot; a failure late in the range is cut before the range is reversed,
//! and the reversal, run whole, replaces the cut when it fits better at all. A round part turned
//! part-way about its own line (it moves nothing) keeps the line: a button (small, squat and
//! smooth on a face of its parent) is pressed along it into its parent, any other round part
//! spun about it, and the other kind is tried when that fails.
//! Variants are swept, and the original weighed, without the end-stop leeway a given joint's
//! written limits get (`SweepParams::end_stop_travel_fraction`): a range this stage writes ends at
//! the stop.

use uniphys_geometry::{DVec3, box_axes, parallel_map, projection_range, symmetric_eigen};
use uniphys_types::{Joint, JointKind, JointLimits};

use crate::VerifyResult;
use crate::candidates::{articulation_candidates, band_pivots, distinct_lines, edge_pivots};
use crate::fit::{may_spin, misfit, round_axis, spin_residual};
use crate::held::{contact_normal_tensor, mean, slide_touch_m, touches};
use crate::in_plane::held_pivots;
use crate::part_box::PartBox;
use crate::round_axis::{RoundAxis, centre_about, push_travel_m};
use crate::rounded_ends::rounded_end_pivots;
use crate::scene::Scene;
use crate::sweep::{SweepMetrics, sweep};
use crate::sweep_params::SweepParams;

/// A corrected joint, what was changed, and the sweep it passed.
#[derive(Debug, Clone, PartialEq)]
pub struct Correction {
    /// The joint that passed.
    pub joint: Joint,
    /// What was changed, for the report.
    pub change: String,
    /// The passing sweep.
    pub metrics: SweepMetrics,
    /// How badly the corrected motion fits the parts it moves (0: perfectly; see `fit`).
    pub misfit: f64,
}

/// Steps of the quick pre-screen sweep run before a full one.
const SCREEN_STEPS: usize = 24;
/// A failed joint whose severity is at most this nearly passed: only its range may change.
const NEARLY_PASSED_SEVERITY: f64 = 2.0;
/// A failure at or beyond this fraction of the way to the limit on its side comes late.
const LATE_FAILURE_FRACTION: f64 = 0.75;
/// Most variants given a full sweep per tier (the best screened ones).
const FULL_SWEEPS_PER_TIER: usize = 3;
/// A later tier's correction replaces an earlier one only when it fits the parts better by
/// this much (see `fit::misfit`); a correction that fits within it ends the search.
const MISFIT_MARGIN: f64 = 0.15;
/// Slide travel tried when a turn becomes a slide, as fractions of the part's extent along the
/// axis (largest first: the range is as far as the part can go).
const SLIDE_TRAVEL_FRACTIONS: [f64; 3] = [0.8, 0.5, 0.25];

/// Presses tried for a round button turned part-way, as fractions of the grounder's stroke
/// ([`push_travel_m`]): the whole stroke, and half of it for a button whose half depth already
/// reaches into the face behind it.
const PRESS_STROKE_FRACTIONS: [f64; 2] = [1.0, 0.5];

/// One way of changing a joint.
struct Variant {
    joint: Joint,
    change: String,
}

/// Tries the variants of a failed `joint` (moving the parts in `moving`), tier by tier, and
/// returns the best passing variant (see the module's documentation), or `None`.
pub fn correct_joint(
    scene: &Scene,
    joint: &Joint,
    moving: &[usize],
    params: &SweepParams,
) -> VerifyResult<Option<Correction>> {
    let original = sweep(scene, joint, moving, params)?;
    correct_failed(scene, joint, moving, params, &original)
}

/// [`correct_joint`] for a joint whose full sweep (`original`) was already run.
pub(crate) fn correct_failed(
    scene: &Scene,
    joint: &Joint,
    moving: &[usize],
    params: &SweepParams,
    original: &SweepMetrics,
) -> VerifyResult<Option<Correction>> {
    // A correction is written here, so it is put at the stops: no end-stop leeway, for the
    // variants nor for the original they are weighed against.
    let params = &SweepParams {
        end_stop_travel_fraction: 0.0,
        ..*params
    };
    let original = &SweepMetrics {
        end_stop_crossed_fraction: 0.0,
        ..original.clone()
    };
    let nearly_passed = original.severity(params) <= NEARLY_PASSED_SEVERITY;
    let screen = SweepParams {
        steps: SCREEN_STEPS,
        ..*params
    };
    let moving_points = scene.points_of(moving);
    // The misfit depends only on the joint and what the sweep measures at rest, so the screen's
    // serves the full sweep too.
    let fit = |m: &SweepMetrics, j: &Joint| {
        misfit(scene, j, moving, &moving_points, m) + cut_penalty(joint, j)
    };
    let mut chosen: Option<Correction> = None;
    // Whether `chosen` cuts the range: the reversal, tried next, still gets its turn.
    let mut chosen_cut = false;
    // The last tier to try after a correction that fits well.
    let mut last_tier: Option<usize> = None;
    // A round part turned part-way about its own line moves nothing: that line is right and the
    // kind of motion wrong, so only the other kinds about it are tried.
    let round_part_way = original.turned_round_part_way(params).is_some();
    let later = std::iter::once_with(|| {
        if round_part_way {
            round_part_tiers(scene, joint)
        } else {
            change_tiers(scene, joint, moving, params, nearly_passed)
        }
    });
    let knob = knob_spin_tiers(scene, joint, original, params);
    // The range tiers' first, where a cut makes way for the reversal.
    let first_range_tier = knob.len();
    for (t, tier) in knob
        .into_iter()
        .chain(range_tiers(joint, original))
        .chain(later.flatten())
        .enumerate()
    {
        if last_tier.is_some_and(|last| t > last) {
            break;
        }
        // Sweeps are independent: each list runs on all cores, and is read in order.
        let screens = parallel_map(&tier, |variant| {
            sweep(scene, &variant.joint, moving, &screen)
        });
        // (preference on the screen, misfit, variant)
        let mut screened: Vec<(Preference, f64, usize)> = Vec::new();
        for (k, (variant, m)) in tier.iter().zip(screens).enumerate() {
            let m = m?;
            if m.failures(&screen).is_empty() {
                let f = fit(&m, &variant.joint);
                screened.push((preference(f, &m, &screen), f, k));
            }
        }
        screened.sort_by(|a, b| compare(a.0, b.0).then(a.2.cmp(&b.2)));
        screened.truncate(FULL_SWEEPS_PER_TIER);
        let full = parallel_map(&screened, |&(_, _, k)| {
            sweep(scene, &tier[k].joint, moving, params)
        });
        let mut passing: Vec<(Preference, f64, usize, SweepMetrics)> = Vec::new();
        for (&(_, f, k), m) in screened.iter().zip(full) {
            let m = m?;
            if m.failures(params).is_empty() {
                passing.push((preference(f, &m, params), f, k, m));
            }
        }
        let Some(best) = (0..passing.len()).min_by(|&a, &b| compare(passing[a].0, passing[b].0))
        else {
            continue;
        };
        // The same motion about a line a few degrees off, listed earlier in the tier (a part's
        // own box axis before a contact axis near it), gives it more exactly: it wins when it
        // fits nearly as well.
        let (_, best_fit, best_k, _) = &passing[best];
        let best = (0..passing.len())
            .filter(|&i| {
                let (_, f, k, _) = &passing[i];
                k < best_k
                    && *f <= best_fit + SAME_MOTION_MISFIT
                    && same_motion_tilted(&tier[*k].joint, &tier[*best_k].joint)
            })
            .min_by_key(|&i| passing[i].2)
            .unwrap_or(best);
        let (_, fit, k, metrics) = passing.swap_remove(best);
        let Variant {
            joint: variant,
            change,
        } = tier.into_iter().nth(k).expect("index of the tier");
        let cut = cut_penalty(joint, &variant) > 0.0;
        // A range run whole the other way replaces a cut one that it fits better by any margin:
        // a motion stopped where it first hit something explains the parts less well.
        let whole_for_cut = chosen_cut
            && variant.kind == joint.kind
            && variant.axis_in_object == joint.axis_in_object
            && variant.pivot_in_object_m == joint.pivot_in_object_m
            && variant.limits == reversed(joint.limits);
        let change = match &chosen {
            None => format!("{change} (misfit {fit:.2})"),
            Some(earlier)
                if (turns(variant.kind) == turns(earlier.joint.kind)
                    || earlier.joint.kind == JointKind::Prismatic)
                    && (fit + MISFIT_MARGIN < earlier.misfit
                        || whole_for_cut && fit < earlier.misfit) =>
            {
                format!(
                    "{change} (misfit {fit:.2}, preferred to {})",
                    earlier.change
                )
            }
            Some(_) => continue,
        };
        chosen_cut = cut;
        chosen = Some(Correction {
            joint: variant,
            change,
            metrics,
            misfit: fit,
        });
        if fit <= MISFIT_MARGIN {
            if cut && t == first_range_tier {
                // The reversal's tier comes next: it is tried, then the search ends.
                last_tier = Some(t + 1);
            } else {
                break;
            }
        }
    }
    Ok(chosen)
}

/// Two joints that move the same way about lines at most [`SQUARE_SNAP_RAD`] apart: the same
/// kind, pivot and range, axes pointing the same way.
fn same_motion_tilted(a: &Joint, b: &Joint) -> bool {
    let (axis_a, axis_b) = (
        DVec3::from_array(a.axis_in_object),
        DVec3::from_array(b.axis_in_object),
    );
    a.kind == b.kind
        && a.pivot_in_object_m == b.pivot_in_object_m
        && a.limits == b.limits
        && axis_a.dot(axis_b) > 0.0
        && line_angle(axis_a, axis_b) <= SQUARE_SNAP_RAD
}

/// An earlier variant of the same motion about a nearby line ([`same_motion_tilted`]) is kept
/// when its misfit is at most this much above the best one's.
const SAME_MOTION_MISFIT: f64 = 0.05;

/// How much a passing variant is preferred, smaller first: its misfit in steps of
/// [`MISFIT_STEP`] (for a slide, the share of its sweep out of contact with its parent: a drawer
/// pulled out runs on its frame, one dropped out of it leaves it at once), then its severity.
type Preference = (i64, f64);

/// The [`Preference`] of a passing variant with `misfit` whose sweep measured `m`.
fn preference(misfit: f64, m: &SweepMetrics, params: &SweepParams) -> Preference {
    ((misfit / MISFIT_STEP).round() as i64, m.severity(params))
}

/// Orders two preferences.
fn compare(a: Preference, b: Preference) -> std::cmp::Ordering {
    a.0.cmp(&b.0).then(a.1.total_cmp(&b.1))
}

/// Steps in which variants' misfits are compared: within one, the margin decides.
const MISFIT_STEP: f64 = 0.01;

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
fn reversed(limits: Option<JointLimits>) -> Option<JointLimits> {
    limits.map(|l| JointLimits {
        lower: -l.upper,
        upper: -l.lower,
    })
}

/// The variants of `joint` that change only its range (tiers 1 and 2).
fn range_tiers(joint: &Joint, original: &SweepMetrics) -> Vec<Vec<Variant>> {
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
fn change_tiers(
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
fn round_part_tiers(scene: &Scene, joint: &Joint) -> Vec<Vec<Variant>> {
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
fn knob_spin_tiers(
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
const SQUARE_SNAP_RAD: f64 = 0.26;

/// Axes closer than this are one candidate, radians (a part's edge and a hinge line from its
/// contact differ by a few degrees on real objects).
const AXIS_MERGE_RAD: f64 = 0.1;

/// How much a variant's range was cut from the original's (same kind), times
/// [`CUT_WEIGHT`]: a motion stopped where it first hit something is a weaker explanation
/// than one that runs its whole range.
fn cut_penalty(original: &Joint, variant: &Joint) -> f64 {
    match (original.limits, variant.limits) {
        (Some(o), Some(v)) if original.kind == variant.kind && o.upper > o.lower => {
            CUT_WEIGHT * (1.0 - (v.upper - v.lower) / (o.upper - o.lower)).clamp(0.0, 1.0)
        }
        _ => 0.0,
    }
}

/// Misfit added per share of the range a correction cuts away.
const CUT_WEIGHT: f64 = 0.5;

/// Angle between two lines (sign ignored), radians.
fn line_angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .abs()
        .clamp(0.0, 1.0)
        .acos()
}

/// Whether a joint of this kind turns. A turn's misfit and a slide's measure different things (a
/// hinge's placement, a slide's hold on its parent and its direction); a turn replaces a slide
/// that fits badly, but a slide that fits well says nothing against a hinge's placement.
fn turns(kind: JointKind) -> bool {
    matches!(kind, JointKind::Revolute | JointKind::Continuous)
}
