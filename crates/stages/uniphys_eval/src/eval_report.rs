//! Evaluation of paired predictions and ground truths into one report over all four tasks.

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use uniphys_mesh_io::IngestOptions;

use crate::annotated::AnnotatedAsset;
use crate::load::{load_ground_truth, load_prediction};
use crate::load_surfaces::{load_ground_truth_with_surfaces, load_prediction_with_surfaces};
use crate::pairing::{PairSamples, pair_samples};
use crate::part_overlap::{PartOverlap, match_parts_by_overlap, renamed_by_overlap};
use crate::{
    EvalError, EvalResult, TaskReport, evaluate_kinematics, evaluate_object, evaluate_physics,
    evaluate_structure,
};

/// Schema version of [`EvalReport`].
pub const EVAL_SCHEMA_VERSION: &str = "uniphys.eval.v1";

/// Task names, in report order.
pub const TASKS: [&str; 4] = [
    "kinematic_parameters",
    "articulation_structure",
    "intrinsic_physics_part",
    "intrinsic_physics_object",
];

/// One evaluated pair, by origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EvalInput {
    /// Where the prediction came from.
    pub pred: String,
    /// Where the ground truth came from.
    pub gt: String,
}

/// What was loaded and matched.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct InputSummary {
    /// Prediction / ground-truth pairs evaluated.
    pub pairs: u64,
    /// GT movable joints (kinematic and structure samples).
    pub gt_movable_joints: u64,
    /// GT movable joints whose child part has a predicted movable joint.
    pub matched_joints: u64,
    /// Predicted movable joints whose child has no GT movable joint (not scored).
    pub extra_pred_movable_joints: u64,
    /// GT parts with physical properties.
    pub gt_parts_with_physics: u64,
    /// Of those, parts with a predicted part of the same name.
    pub matched_parts: u64,
    /// Ground truths with object values.
    pub gt_objects: u64,
}

/// The report of `uniphys eval`: per task the reference's `paper_metrics`, `counts` and
/// `extra_metrics`, plus what was loaded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EvalReport {
    /// [`EVAL_SCHEMA_VERSION`].
    pub schema_version: String,
    /// The pairs, in order.
    pub inputs: Vec<EvalInput>,
    /// Loading and matching counts.
    pub input_summary: InputSummary,
    /// One report per task of [`TASKS`], by name.
    pub tasks: BTreeMap<String, TaskReport>,
}

impl EvalReport {
    /// The report of a task by name.
    #[must_use]
    pub fn task(&self, name: &str) -> Option<&TaskReport> {
        self.tasks.get(name)
    }
}

/// Evaluates `(prediction, ground truth)` pairs.
#[must_use]
pub fn evaluate_pairs(pairs: &[(AnnotatedAsset, AnnotatedAsset)]) -> EvalReport {
    let mut all = PairSamples::default();
    let mut summary = InputSummary::default();
    for (pred, gt) in pairs {
        let s = pair_samples(pred, gt);
        summary.pairs += 1;
        summary.gt_movable_joints += s.kinematics.len() as u64;
        summary.matched_joints += s.matched_joints;
        summary.extra_pred_movable_joints += s.extra_pred_movable_joints;
        summary.gt_parts_with_physics += s.physics.len() as u64;
        summary.matched_parts += s.matched_parts;
        summary.gt_objects += s.object.len() as u64;
        all.kinematics.extend(s.kinematics);
        all.structure.extend(s.structure);
        all.physics.extend(s.physics);
        all.object.extend(s.object);
    }
    let tasks = BTreeMap::from([
        (TASKS[0].to_owned(), evaluate_kinematics(&all.kinematics)),
        (TASKS[1].to_owned(), evaluate_structure(&all.structure)),
        (TASKS[2].to_owned(), evaluate_physics(&all.physics)),
        (TASKS[3].to_owned(), evaluate_object(&all.object)),
    ]);
    EvalReport {
        schema_version: EVAL_SCHEMA_VERSION.to_owned(),
        inputs: pairs
            .iter()
            .map(|(p, g)| EvalInput {
                pred: p.origin.clone(),
                gt: g.origin.clone(),
            })
            .collect(),
        input_summary: summary,
        tasks,
    }
}

/// Loads predictions and ground truths from paths, pairs them in order and evaluates them.
///
/// # Errors
/// [`EvalError::Mismatch`] when the lists are empty or of different lengths; a loading error
/// of the first path that fails otherwise (its message names the path).
pub fn evaluate_paths(
    preds: &[PathBuf],
    gts: &[PathBuf],
    gt_options: &IngestOptions,
) -> EvalResult<EvalReport> {
    Ok(evaluate_pairs(&load_pairs(preds, gts, gt_options)?))
}

/// Loads predictions and ground truths paired in order (see [`evaluate_paths`]).
///
/// # Errors
/// [`EvalError::Mismatch`] when either list is empty or their lengths differ; any load error.
pub fn load_pairs(
    preds: &[PathBuf],
    gts: &[PathBuf],
    gt_options: &IngestOptions,
) -> EvalResult<Vec<(AnnotatedAsset, AnnotatedAsset)>> {
    check_paired(preds, gts)?;
    preds
        .iter()
        .zip(gts)
        .map(|(p, g)| Ok((load_prediction(p)?, load_ground_truth(g, gt_options)?)))
        .collect()
}

/// A prediction and its ground truth.
pub type PredictionAndTruth = (AnnotatedAsset, AnnotatedAsset);

/// Loads predictions and ground truths paired in order as [`load_pairs`] does, and pairs each
/// prediction's parts with the true parts by shared surface ([`match_parts_by_overlap`]): the
/// prediction comes back renamed to the true parts' names ([`renamed_by_overlap`]), with the
/// part matches.
///
/// # Errors
/// As [`load_pairs`]; a prediction without its output directory's part meshes, or a ground
/// truth without part meshes (a UniPhys-40K entity), is a load error.
pub fn load_pairs_by_overlap(
    preds: &[PathBuf],
    gts: &[PathBuf],
    gt_options: &IngestOptions,
) -> EvalResult<Vec<(PredictionAndTruth, Vec<PartOverlap>)>> {
    check_paired(preds, gts)?;
    preds
        .iter()
        .zip(gts)
        .map(|(p, g)| {
            let (pred, pred_surfaces) = load_prediction_with_surfaces(p)?;
            let (gt, gt_surfaces) = load_ground_truth_with_surfaces(g, gt_options)?;
            let matches = match_parts_by_overlap(&pred, &pred_surfaces, &gt, &gt_surfaces)?;
            Ok(((renamed_by_overlap(&pred, &matches), gt), matches))
        })
        .collect()
}

/// Both lists given and of one length.
fn check_paired(preds: &[PathBuf], gts: &[PathBuf]) -> EvalResult<()> {
    if preds.is_empty() || gts.is_empty() {
        return Err(EvalError::Mismatch(
            "give at least one prediction and one ground truth (--pred and --gt)".to_owned(),
        ));
    }
    if preds.len() != gts.len() {
        return Err(EvalError::Mismatch(format!(
            "{} predictions but {} ground truths: --pred and --gt are paired in order, so give as many of each",
            preds.len(),
            gts.len()
        )));
    }
    Ok(())
}
