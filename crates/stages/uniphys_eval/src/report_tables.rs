//! The [`EvalReport`] as Markdown tables, one per task, for terminals and notes.

use std::fmt::Write as _;

use crate::{EvalReport, TASKS};

/// A metric value with 4 decimals, or `n/a` when no pair contributed.
#[must_use]
pub fn format_metric(value: Option<f64>) -> String {
    value.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.4}"))
}

/// Markdown: the input summary, then per task its paper metrics, extra metrics and counts.
#[must_use]
pub fn report_tables(report: &EvalReport) -> String {
    let s = &report.input_summary;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} pairs; GT movable joints {} (matched by child part name: {}, extra predicted: {}); GT parts with physics {} (matched by name: {}); GT objects {}\n",
        s.pairs,
        s.gt_movable_joints,
        s.matched_joints,
        s.extra_pred_movable_joints,
        s.gt_parts_with_physics,
        s.matched_parts,
        s.gt_objects
    );
    for task in TASKS {
        let Some(t) = report.task(task) else { continue };
        let _ = writeln!(out, "### {task}\n\n| metric | value |\n|---|---|");
        for (name, value) in &t.paper_metrics {
            let _ = writeln!(out, "| {name} | {} |", format_metric(*value));
        }
        for (name, value) in &t.extra_metrics {
            let _ = writeln!(out, "| {name} (extra) | {} |", format_metric(*value));
        }
        let counts: Vec<String> = t.counts.iter().map(|(k, v)| format!("{k} {v}")).collect();
        let _ = writeln!(out, "\ncounts: {}\n", counts.join(", "));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluate_pairs;

    #[test]
    fn empty_report_prints_every_task_with_missing_metrics() {
        let text = report_tables(&evaluate_pairs(&[]));
        for task in TASKS {
            assert!(text.contains(&format!("### {task}")), "{text}");
        }
        assert!(text.contains("| joint_type_accuracy | n/a |"), "{text}");
        assert_eq!(format_metric(Some(0.5)), "0.5000");
    }
}
