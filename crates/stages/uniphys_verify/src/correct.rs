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
//!
//! The tiers of variants are built in `variants`; this module sweeps them and chooses.

use uniphys_geometry::{DVec3, parallel_map};
use uniphys_types::{Joint, JointKind};

use crate::VerifyResult;
use crate::fit::misfit;
use crate::scene::Scene;
use crate::sweep::{SweepMetrics, sweep};
use crate::sweep_params::SweepParams;
use crate::variants::{
    SQUARE_SNAP_RAD, Variant, change_tiers, knob_spin_tiers, line_angle, range_tiers, reversed,
    round_part_tiers,
};

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
/// Most variants given a full sweep per tier (the best screened ones).
const FULL_SWEEPS_PER_TIER: usize = 3;
/// A later tier's correction replaces an earlier one only when it fits the parts better by
/// this much (see `fit::misfit`); a correction that fits within it ends the search.
const MISFIT_MARGIN: f64 = 0.15;
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

/// Whether a joint of this kind turns. A turn's misfit and a slide's measure different things (a
/// hinge's placement, a slide's hold on its parent and its direction); a turn replaces a slide
/// that fits badly, but a slide that fits well says nothing against a hinge's placement.
fn turns(kind: JointKind) -> bool {
    matches!(kind, JointKind::Revolute | JointKind::Continuous)
}
