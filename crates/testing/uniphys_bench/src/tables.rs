//! Markdown tables: the paper's PartNet-Mobility rows next to ours, per-asset rows, skips.

use std::fmt::Write as _;

use uniphys_eval::{EvalReport, TaskReport};

use crate::assets::Skipped;
use crate::pose_run::{Pose, PoseResult, pose_label};

/// The paper's PartNet-Mobility rows: joint type accuracy %, axis error degrees, pivot error in
/// the [0, 2] frame, limit mIoU %.
const PAPER_ROWS: [(&str, f64, f64, f64, f64); 3] = [
    ("URDFormer", 70.91, 10.39, 0.620, 83.92),
    ("Articulate-Anything", 100.0, 7.97, 0.471, 77.20),
    ("UniPhysGen", 98.80, 8.84, 0.084, 91.45),
];

fn kinematics(report: &EvalReport) -> Option<&TaskReport> {
    report.task("kinematic_parameters")
}

fn percent(v: Option<f64>) -> String {
    v.map_or_else(|| "n/a".to_owned(), |v| format!("{:.2}", 100.0 * v))
}

fn fixed(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.decimals$}"))
}

/// The paper's four kinematic metrics, in table order: joint type accuracy, axis error, pivot
/// error, limit mIoU.
const PAPER_METRICS: [&str; 4] = [
    "joint_type_accuracy",
    "axis_angular_error_degrees",
    "pivot_distance_error_aabb_0_2",
    "limit_miou",
];

/// The four paper metrics of a report as table cells.
pub(crate) fn metric_cells(k: Option<&TaskReport>) -> String {
    cells(PAPER_METRICS.map(|name| k.and_then(|k| k.paper(name))))
}

/// Values of the [`PAPER_METRICS`] as table cells (percentages, degrees, the [0, 2] frame).
fn cells([acc, axis, pivot, limit]: [Option<f64>; 4]) -> String {
    format!(
        "{} | {} | {} | {}",
        percent(acc),
        fixed(axis, 2),
        fixed(pivot, 3),
        percent(limit),
    )
}

fn counts(k: Option<&TaskReport>) -> String {
    let c = |name: &str| k.map_or(0, |k| k.count(name));
    format!(
        "{} | {} | {} | {}",
        c("joint_type"),
        c("axis"),
        c("pivot"),
        c("limit")
    )
}

/// The section of one pose: the comparison table, then one row per asset.
pub(crate) fn pose_section(pose: Pose, result: &PoseResult) -> String {
    let mut out = String::new();
    let overall = kinematics(&result.overall);
    let s = &result.overall.input_summary;
    let matching = match result.recovered {
        Some((found, all)) => format!(
            "parts paired with the true ones by shared surface ({found} of {all} moving true parts found), then "
        ),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "## {} ({} assets, {} GT movable joints, {} matched by {matching}child part name; {:.1} s)\n",
        pose_label(pose),
        result.rows.len(),
        s.gt_movable_joints,
        s.matched_joints,
        result.wall_time.as_secs_f64()
    );
    let _ = writeln!(
        out,
        "| method | data | joint type acc (%) ↑ | axis err (°) ↓ | pivot err ([0,2]) ↓ | limit mIoU (%) ↑ |\n|---|---|---|---|---|---|"
    );
    for (name, acc, axis, pivot, limit) in PAPER_ROWS {
        let _ = writeln!(
            out,
            "| {name} (paper) | PartNet-Mobility | {acc:.2} | {axis:.2} | {pivot:.3} | {limit:.2} |"
        );
    }
    for (group, count, report) in &result.groups {
        let _ = writeln!(
            out,
            "| UniPhys pipeline, this build | {group}: {count}, joints stripped ({} GT joints) | {} |",
            report.input_summary.gt_movable_joints,
            metric_cells(kinematics(report))
        );
    }
    let _ = writeln!(
        out,
        "| UniPhys pipeline, this build | all {} assets here, joints stripped | {} |\n",
        result.rows.len(),
        metric_cells(overall)
    );
    let _ = writeln!(
        out,
        "| asset | GT movable | matched | extra predicted | type acc (%) | axis (°) | pivot | limit mIoU (%) | n type / axis / pivot / limit | run (s) |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for row in &result.rows {
        let k = kinematics(&row.report);
        let s = &row.report.input_summary;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {:.2} |",
            row.name,
            s.gt_movable_joints,
            s.matched_joints,
            s.extra_pred_movable_joints,
            metric_cells(k),
            counts(k).replace(" | ", " / "),
            row.run_time.as_secs_f64()
        );
    }
    out
}

/// The four paper metrics of every pass side by side, the rotated passes' mean, and how far
/// each rotated pass's axis error lies from the upright one's (the pose-independence check).
pub(crate) fn poses_section(passes: &[(Pose, EvalReport)]) -> String {
    let value = |report: &EvalReport, name: &str| kinematics(report).and_then(|k| k.paper(name));
    let upright_axis = passes
        .iter()
        .find(|(pose, _)| *pose == Pose::Upright)
        .and_then(|(_, r)| value(r, PAPER_METRICS[1]));
    let mut out = String::from(
        "## Poses compared\n\n| pose | joint type acc (%) ↑ | axis err (°) ↓ | pivot err ([0,2]) ↓ | limit mIoU (%) ↑ | axis err − upright (°) |\n|---|---|---|---|---|---|\n",
    );
    let rotated: Vec<&EvalReport> = passes
        .iter()
        .filter(|(pose, _)| *pose != Pose::Upright)
        .map(|(_, r)| r)
        .collect();
    let against_upright = |axis: Option<f64>| match (axis, upright_axis) {
        (Some(a), Some(u)) => format!("{:+.2}", a - u),
        _ => "n/a".to_owned(),
    };
    for (pose, report) in passes {
        let _ = writeln!(
            out,
            "| {} | {} | {} |",
            pose_label(*pose),
            metric_cells(kinematics(report)),
            against_upright(value(report, PAPER_METRICS[1]))
        );
    }
    if !rotated.is_empty() {
        let mean = |name: &str| {
            let values: Vec<f64> = rotated.iter().filter_map(|r| value(r, name)).collect();
            (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
        };
        let means = PAPER_METRICS.map(mean);
        let _ = writeln!(
            out,
            "| mean of the {} rotated passes | {} | {} |",
            rotated.len(),
            cells(means),
            against_upright(means[1])
        );
    }
    out
}

/// The assets left out, with reasons.
pub(crate) fn skipped_section(skipped: &[Skipped]) -> String {
    if skipped.is_empty() {
        return "No asset was skipped.\n".to_owned();
    }
    let mut out = format!(
        "## Skipped ({})\n\n| asset | reason |\n|---|---|\n",
        skipped.len()
    );
    for s in skipped {
        let reason = s.reason.replace('|', "/").replace('\n', " ");
        let _ = writeln!(out, "| {} | {reason} |", s.name);
    }
    out
}
