//! Tables read joint by joint: a confusion matrix of joint kinds, per-category rows and every
//! ground-truth movable joint next to the predicted one.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use uniphys_eval::{
    AnnotatedAsset, AnnotatedJoint, axis_angular_error_degrees, evaluate_pairs, interval_iou,
    pair_samples, point_to_line_distance,
};

use crate::pose_run::PoseResult;
use crate::tables::metric_cells;

/// Kind of an annotated joint as a word: `B` is a slide, `C` a turn (a full-turn range is read as
/// continuous), `D` fixed; `none` when the part has no joint.
fn kind_word(joint: Option<&AnnotatedJoint>) -> &'static str {
    match joint {
        None => "none",
        Some(j) => match j.motion_type {
            'B' => "prismatic",
            'C' => {
                let full = j
                    .range
                    .is_some_and(|r| (r[1] - r[0]).abs() >= std::f64::consts::TAU - 1e-6);
                if full { "continuous" } else { "revolute" }
            }
            _ => "fixed",
        },
    }
}

const KINDS: [&str; 5] = ["prismatic", "revolute", "continuous", "fixed", "none"];

/// One ground-truth movable joint next to its prediction.
struct JointRow<'a> {
    asset: &'a str,
    category: &'a str,
    child: &'a str,
    gt: &'static str,
    pred: &'static str,
    axis_deg: Option<f64>,
    pivot: Option<f64>,
    limit_iou: Option<f64>,
    /// Ground-truth and predicted ranges (radians, or the frame's units for slides).
    gt_range: Option<[f64; 2]>,
    pred_range: Option<[f64; 2]>,
}

fn joint_rows(result: &PoseResult) -> Vec<JointRow<'_>> {
    let mut out = Vec::new();
    for row in &result.rows {
        let (pred, gt) = &row.pair;
        let samples = pair_samples(pred, gt);
        let movable = gt.joints.iter().filter(|j| j.is_movable());
        for (g, sample) in movable.zip(&samples.kinematics) {
            let p = pred.joint_of(&g.child);
            let same_type = p.is_some_and(|p| p.motion_type == g.motion_type);
            let prediction = sample.pred.as_ref().filter(|_| same_type);
            let axis_deg = prediction
                .and_then(|p| p.axis)
                .and_then(|a| axis_angular_error_degrees(a, g.axis));
            let pivot = prediction.filter(|_| g.motion_type == 'C').and_then(|p| {
                point_to_line_distance(p.pivot_model?, sample.gt_pivot_model?, g.axis)
            });
            let scale = if g.motion_type == 'B' {
                sample.frame_scale
            } else {
                Some(1.0)
            };
            let scaled = |r: Option<[f64; 2]>| {
                let s = scale?;
                Some(r?.map(|v| v / s))
            };
            let gt_range = scaled(sample.gt_range);
            let pred_range = scaled(sample.pred.as_ref().and_then(|p| p.range));
            let limit_iou = prediction.and_then(|_| interval_iou(pred_range?, gt_range?));
            out.push(JointRow {
                asset: &row.name,
                category: &row.category,
                child: &g.child,
                gt: kind_word(Some(g)),
                pred: kind_word(p),
                axis_deg,
                pivot,
                limit_iou,
                gt_range,
                pred_range: pred_range.filter(|_| same_type),
            });
        }
    }
    out
}

fn range_cell(r: Option<[f64; 2]>) -> String {
    r.map_or_else(|| "-".to_owned(), |[lo, hi]| format!("[{lo:.2}, {hi:.2}]"))
}

fn cell(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.decimals$}"))
}

/// The confusion matrix of joint kinds, per-category rows and the per-joint list.
pub(crate) fn joint_sections(result: &PoseResult) -> String {
    let rows = joint_rows(result);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "### Joint kinds: ground truth (rows) against prediction (columns)\n\n| GT \\ predicted | {} |\n|---|{}",
        KINDS.join(" | "),
        "---|".repeat(KINDS.len())
    );
    for gt in KINDS.iter().take(3) {
        let counts: Vec<String> = KINDS
            .iter()
            .map(|p| {
                rows.iter()
                    .filter(|r| r.gt == *gt && r.pred == *p)
                    .count()
                    .to_string()
            })
            .collect();
        let _ = writeln!(out, "| {gt} | {} |", counts.join(" | "));
    }
    let mut by_category: BTreeMap<&str, Vec<(AnnotatedAsset, AnnotatedAsset)>> = BTreeMap::new();
    let mut time: BTreeMap<&str, f64> = BTreeMap::new();
    for row in result.rows.iter().filter(|r| !r.category.is_empty()) {
        by_category
            .entry(&row.category)
            .or_default()
            .push(row.pair.clone());
        *time.entry(&row.category).or_default() += row.run_time.as_secs_f64();
    }
    if !by_category.is_empty() {
        let _ = writeln!(
            out,
            "\n### Per category\n\n| category | objects | GT joints | joint type acc (%) | axis err (°) | pivot err ([0,2]) | limit mIoU (%) | mean run (s) |\n|---|---|---|---|---|---|---|---|"
        );
        for (category, pairs) in &by_category {
            let report = evaluate_pairs(pairs);
            let _ = writeln!(
                out,
                "| {category} | {} | {} | {} | {:.1} |",
                pairs.len(),
                report.input_summary.gt_movable_joints,
                metric_cells(report.task("kinematic_parameters")),
                time[category] / pairs.len() as f64
            );
        }
    }
    let _ = writeln!(
        out,
        "\n### Every ground-truth movable joint\n\n| asset | category | part | GT | predicted | axis err (°) | pivot err | GT range | predicted range | limit IoU |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for r in &rows {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.asset,
            r.category,
            r.child,
            r.gt,
            r.pred,
            cell(r.axis_deg, 1),
            cell(r.pivot, 3),
            range_cell(r.gt_range),
            range_cell(r.pred_range),
            cell(r.limit_iou, 2)
        );
    }
    out
}
