//! Tables read joint by joint: a confusion matrix of joint kinds, per-category rows and every
//! ground-truth movable joint next to the predicted one.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use uniphys_eval::{
    AnnotatedAsset, JointComparison, compare_joints, evaluate_pairs, per_joint_table,
};

use crate::pose_run::PoseResult;
use crate::tables::metric_cells;

const KINDS: [&str; 5] = ["prismatic", "revolute", "continuous", "fixed", "none"];

/// Every ground-truth movable joint of the pose's assets next to its prediction.
fn joint_rows(result: &PoseResult) -> Vec<JointComparison> {
    result
        .rows
        .iter()
        .flat_map(|row| compare_joints(&row.name, &row.pair.0, &row.pair.1))
        .collect()
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
                    .filter(|r| r.gt_kind == *gt && r.predicted_kind == *p)
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
    let _ = write!(
        out,
        "\n### Every ground-truth movable joint\n\n{}",
        per_joint_table(&rows)
    );
    out
}
