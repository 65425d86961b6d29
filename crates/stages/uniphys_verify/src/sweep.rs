//! The articulation sweep (reference 12, kinematic): move a joint through its range and measure
//! contact with the parent and interpenetration with everything that stays still.

use std::collections::BTreeMap;

use uniphys_geometry::{DVec3, KdTree, fit_plane};
use uniphys_types::{Joint, JointKind};

use crate::motion::{JointMotion, sweep_coordinates};
use crate::patch::{PatchParams, grow_patch, mean_spacing_m};
use crate::scene::Scene;
use crate::{VerifyError, VerifyResult};

/// Parameters of a sweep. Distances are fractions of the object diagonal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepParams {
    /// Joint coordinates visited, both limits included (reference: 200).
    pub steps: usize,
    /// Contact threshold search.
    pub patch: PatchParams,
    /// Failure when the 95th percentile of the contact thickness ratio exceeds this (reference: 3).
    pub thickness_ratio_max: f64,
    /// A step's contact overlap below this is bad (reference: 0.4).
    pub overlap_min: f64,
    /// Rotational joints fail when more than this fraction of steps has bad overlap and the
    /// 10th percentile is bad too (reference: 0.1).
    pub bad_overlap_fraction_max: f64,
    /// Interpenetration of colliders beyond their overlap at rest that fails the joint.
    pub penetration_tolerance_fraction: f64,
    /// Seed of the candidate search of corrections.
    pub seed: u64,
}

impl Default for SweepParams {
    /// 200 steps, the reference's ratios, penetration tolerance 1.5 % of the diagonal.
    fn default() -> Self {
        Self {
            steps: 200,
            patch: PatchParams::default(),
            thickness_ratio_max: 3.0,
            overlap_min: 0.4,
            bad_overlap_fraction_max: 0.1,
            penetration_tolerance_fraction: 0.015,
            seed: 7,
        }
    }
}

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
/// interpenetration, which those metrics stood in for, is measured directly on the colliders. Penetration: for each pair of a moving
/// and a still convex collider, the contact depth (parry, GJK/EPA) minus its depth at rest.
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
    let still: Vec<usize> = (0..n).filter(|p| !moving.contains(p)).collect();
    let colliders = &scene.colliders;
    let moving_hulls = colliders.of_parts(moving);
    let still_hulls = colliders.of_parts(&still);
    let rest_pose = colliders.pose(&motion, 0.0);
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
    let initial = grow_patch(
        parent_points,
        &KdTree::new(moving_points.clone()),
        start,
        step,
        patch.initial_increments(),
        patch.min_points,
    );
    let reference = match &initial {
        Some((points, threshold)) => Some(ContactReference::new(points, *threshold)?),
        None => None,
    };

    let tolerance = params.penetration_tolerance_fraction * diag;
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
    };
    let mut thickness = Vec::new();
    let mut overlap = Vec::new();
    let mut growth_sum = 0.0;
    for q in sweep_coordinates(lower, upper, params.steps) {
        let pose = colliders.pose(&motion, q);
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
        if let Some(reference) = &reference {
            let to_object = motion.object_from_moved(q);
            let moved: Vec<DVec3> = moving_points
                .iter()
                .map(|p| to_object.transform_point3(*p))
                .collect();
            let found = grow_patch(
                parent_points,
                &KdTree::new(moved),
                reference.threshold_m,
                step,
                patch.max_step_increments,
                patch.min_points,
            );
            match found {
                Some((points, threshold)) => {
                    metrics.contact_steps += 1;
                    thickness.push(reference.thickness_ratio(&points, threshold)?);
                    overlap.push(reference.overlap_ratio(&points));
                }
                None => metrics.lost_contact_steps += 1,
            }
        }
    }
    metrics.mean_penetration_growth_m = growth_sum / params.steps.max(1) as f64;
    if !thickness.is_empty() {
        metrics.thickness_ratio_p95 = percentile(&mut thickness, 95.0);
        metrics.bad_overlap_fraction = overlap.iter().filter(|&&o| o < params.overlap_min).count()
            as f64
            / overlap.len() as f64;
        metrics.overlap_ratio_p10 = percentile(&mut overlap, 10.0);
    }
    Ok(metrics)
}

/// The contact at rest that later steps are compared with.
struct ContactReference {
    threshold_m: f64,
    thickness_m: f64,
    points: Vec<DVec3>,
    tree: KdTree,
    overlap_radius_m: f64,
}

impl ContactReference {
    fn new(points: &[DVec3], threshold_m: f64) -> VerifyResult<Self> {
        Ok(Self {
            threshold_m,
            thickness_m: thickness_m(points)?,
            points: points.to_vec(),
            tree: KdTree::new(points.to_vec()),
            overlap_radius_m: 2.0 * mean_spacing_m(points),
        })
    }

    /// Thickness of a step's contact over the initial thickness, the latter at least the
    /// threshold that found the step's points (a band of points within a threshold of a surface
    /// is that thick; without the floor a thin initial contact makes any later one look thick).
    fn thickness_ratio(&self, points: &[DVec3], threshold_m: f64) -> VerifyResult<f64> {
        Ok(thickness_m(points)? / self.thickness_m.max(threshold_m))
    }

    /// How much of one contact the other covers: the larger of the fraction of the step's
    /// points near an initial point and the fraction of initial points near a step's point
    /// (within the overlap radius). A lid opening keeps part of its initial contact (the
    /// hinge line), a lid closing adds to it; a contact that slides elsewhere does neither.
    fn overlap_ratio(&self, points: &[DVec3]) -> f64 {
        if self.points.is_empty() || points.is_empty() {
            return 0.0;
        }
        let covered = |of: &[DVec3], by: &KdTree| {
            of.iter()
                .filter(|p| by.nearest_distance(**p) <= self.overlap_radius_m)
                .count() as f64
                / of.len() as f64
        };
        let now = KdTree::new(points.to_vec());
        covered(points, &self.tree).max(covered(&self.points, &now))
    }
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

/// Percentile with linear interpolation between closest ranks (numpy's default).
fn percentile(values: &mut [f64], pct: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let rank = pct / 100.0 * (values.len() - 1) as f64;
    let (lo, hi) = (rank.floor() as usize, rank.ceil() as usize);
    values[lo] + (values[hi] - values[lo]) * (rank - lo as f64)
}

impl SweepMetrics {
    /// Why the joint fails, empty when it passes:
    /// - the child does not touch its parent at rest;
    /// - rotational joints: contact lost at some step, or severe overlap change (more than
    ///   `bad_overlap_fraction_max` of steps below `overlap_min` and the 10th percentile too);
    /// - any joint: the 95th percentile thickness ratio above `thickness_ratio_max`;
    /// - any joint: a moving collider penetrates a still one deeper than at rest by more than the
    ///   penetration tolerance.
    #[must_use]
    pub fn failures(&self, params: &SweepParams) -> Vec<String> {
        let mut reasons = Vec::new();
        if self.initial_contact_points == 0 {
            reasons.push("the moving part does not touch its parent at rest".to_owned());
        }
        let rotational = matches!(self.kind, JointKind::Revolute | JointKind::Continuous);
        if rotational && self.initial_contact_points > 0 && self.lost_contact_steps > 0 {
            reasons.push(format!(
                "hinge lost contact with its parent in {} of {} steps",
                self.lost_contact_steps, self.steps
            ));
        }
        if rotational
            && self.bad_overlap_fraction > params.bad_overlap_fraction_max
            && self.overlap_ratio_p10 < params.overlap_min
            && self.contact_steps > 0
        {
            reasons.push(format!(
                "severe contact overlap change: p10 = {:.3}, bad fraction = {:.3}",
                self.overlap_ratio_p10, self.bad_overlap_fraction
            ));
        }
        if self.thickness_ratio_p95 > params.thickness_ratio_max {
            reasons.push(format!(
                "severe contact thickness change: p95 ratio = {:.2}",
                self.thickness_ratio_p95
            ));
        }
        if self.penetrating_steps > 0 {
            let part = self
                .worst_part
                .map_or_else(|| "?".to_owned(), |p| p.to_string());
            reasons.push(format!(
                "penetrates part {part} by {:.4} m at coordinate {:.4} ({} of {} steps beyond {:.4} m)",
                self.max_penetration_growth_m,
                self.worst_coordinate,
                self.penetrating_steps,
                self.steps,
                self.penetration_tolerance_m
            ));
        }
        reasons
    }

    /// The metrics by name, units in the names.
    #[must_use]
    pub fn as_map(&self) -> BTreeMap<String, f64> {
        let entries = [
            ("steps", self.steps as f64),
            ("initial_contact_points", self.initial_contact_points as f64),
            ("contact_threshold_m", self.contact_threshold_m),
            ("contact_steps", self.contact_steps as f64),
            ("lost_contact_steps", self.lost_contact_steps as f64),
            ("thickness_ratio_p95", self.thickness_ratio_p95),
            ("overlap_ratio_p10", self.overlap_ratio_p10),
            ("bad_overlap_fraction", self.bad_overlap_fraction),
            ("max_penetration_growth_m", self.max_penetration_growth_m),
            ("mean_penetration_growth_m", self.mean_penetration_growth_m),
            ("penetrating_steps", self.penetrating_steps as f64),
            ("penetration_tolerance_m", self.penetration_tolerance_m),
            ("worst_coordinate", self.worst_coordinate),
        ];
        entries
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .collect()
    }
}
