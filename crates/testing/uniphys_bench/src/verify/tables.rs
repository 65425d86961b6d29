//! The Markdown tables and the JSON of `verify-bench`.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde_json::json;
use uniphys_types::{CheckOutcome, Joint, JointKind};
use uniphys_verify::SweepParams;

use crate::breakage::Breakage;
use crate::object::{JointResult, ObjectResult};

/// Pivot candidate distance a rotating joint's nearest candidate should be within, [0,2] frame.
const PIVOT_TARGET_MODEL: f64 = 0.02;
/// Time one sweep of a joint should stay under, ms (issue 18).
const SWEEP_TARGET_MS: f64 = 50.0;

type Results = [(String, anyhow::Result<ObjectResult>)];

fn pct(n: usize, d: usize) -> String {
    if d == 0 {
        "-".to_owned()
    } else {
        format!("{:.1} %", 100.0 * n as f64 / d as f64)
    }
}

fn joints(results: &Results) -> impl Iterator<Item = (&str, &ObjectResult, &JointResult)> {
    results
        .iter()
        .filter_map(|(name, r)| r.as_ref().ok().map(|o| (name.as_str(), o)))
        .flat_map(|(name, o)| o.joints.iter().map(move |j| (name, o, j)))
}

/// The whole report.
pub(crate) fn report(results: &Results) -> String {
    let mut out = String::from("# Verification of true joints of real objects\n\n");
    let ok = results.iter().filter(|(_, r)| r.is_ok()).count();
    let _ = writeln!(out, "{ok} objects judged, {} skipped\n", results.len() - ok);
    out.push_str(&true_joint_table(
        results,
        |j| j.kind.as_str().to_owned(),
        "kind",
    ));
    out.push_str(&true_joint_table(
        results,
        |j| format!("{} {}", j.kind.as_str(), j.label),
        "kind and part label",
    ));
    out.push_str(&failure_list(results));
    out.push_str(&breakage_table(results));
    out.push_str(&pivot_table(results));
    out.push_str(&time_line(results));
    out
}

/// Counts of true-joint outcomes.
#[derive(Default)]
struct Counts {
    total: usize,
    pass: usize,
    corrected: usize,
    corrected_wrong: usize,
    fail: usize,
}

impl Counts {
    fn add(&mut self, j: &JointResult) {
        self.total += 1;
        match j.outcome {
            CheckOutcome::Pass => self.pass += 1,
            CheckOutcome::Warn => self.corrected += 1,
            CheckOutcome::Fail | CheckOutcome::Skipped => self.fail += 1,
        }
        self.corrected_wrong += usize::from(j.corrected_wrong);
    }

    fn row(&self, key: &str) -> String {
        format!(
            "| {key} | {} | {} | {} | {} | {} | {} |\n",
            self.total,
            self.pass,
            self.corrected,
            self.corrected_wrong,
            self.fail,
            pct(self.pass, self.total)
        )
    }
}

fn true_joint_table(results: &Results, key: impl Fn(&JointResult) -> String, by: &str) -> String {
    let mut rows: BTreeMap<String, Counts> = BTreeMap::new();
    let mut all = Counts::default();
    for (_, _, j) in joints(results) {
        rows.entry(key(j)).or_default().add(j);
        all.add(j);
    }
    let mut out = format!(
        "## True joints given to the verifier as a grounder's, by {by}\n\n| {by} | joints | pass unchanged | corrected | corrected to a wrong joint | failed | pass % |\n|---|---:|---:|---:|---:|---:|---:|\n"
    );
    for (k, r) in &rows {
        out.push_str(&r.row(k));
    }
    out.push_str(&all.row("**all**"));
    out.push('\n');
    out
}

fn failure_list(results: &Results) -> String {
    let mut out = String::from(
        "## True joints not passed unchanged\n\n| object | category | joint | kind | label | outcome | why |\n|---|---|---|---|---|---|---|\n",
    );
    for (name, o, j) in joints(results).filter(|(_, _, j)| !j.passed_unchanged()) {
        let _ = writeln!(
            out,
            "| {name} | {} | {} | {} | {} | {:?}{} | {} |",
            o.category,
            j.joint,
            j.kind.as_str(),
            j.label,
            j.outcome,
            if j.corrected_wrong { " (wrong)" } else { "" },
            j.message.replace('|', "/")
        );
    }
    for (name, r) in results {
        if let Err(e) = r {
            let _ = writeln!(
                out,
                "| {name} | | | | | skipped | {} |",
                format!("{e:#}").replace('|', "/")
            );
        }
    }
    out.push('\n');
    out
}

fn breakage_table(results: &Results) -> String {
    let mut out = String::from(
        "## True joints broken on purpose\n\nRestored: the correction gives the true kind of motion, axis (within 2 degrees) and pivot line (within 0.05 of the [0,2] frame), moving the part the true way (half of its range or more within the true range); the last columns ask instead for a range whose intersection over union with the true one is a half or more.\n\n| breakage | joints | caught | caught % | restored to the truth | restored % | and the range (IoU >= 0.5) | % |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let (mut total, mut caught, mut restored, mut ranged) = (0, 0, 0, 0);
    for b in Breakage::ALL {
        let rows: Vec<_> = joints(results)
            .flat_map(|(_, _, j)| j.breakages.iter())
            .filter(|r| r.breakage == b)
            .collect();
        let c = rows.iter().filter(|r| r.caught).count();
        let r = rows.iter().filter(|r| r.restored).count();
        let g = rows.iter().filter(|r| r.restored_range).count();
        let _ = writeln!(
            out,
            "| {} | {} | {c} | {} | {r} | {} | {g} | {} |",
            b.name(),
            rows.len(),
            pct(c, rows.len()),
            pct(r, rows.len()),
            pct(g, rows.len())
        );
        total += rows.len();
        caught += c;
        restored += r;
        ranged += g;
    }
    let _ = writeln!(
        out,
        "| **all** | {total} | {caught} | {} | {restored} | {} | {ranged} | {} |\n",
        pct(caught, total),
        pct(restored, total),
        pct(ranged, total)
    );
    out
}

fn pivot_table(results: &Results) -> String {
    let mut by_kind: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    let mut missing = 0;
    for (_, _, j) in joints(results) {
        if !matches!(j.kind, JointKind::Revolute | JointKind::Continuous) {
            continue;
        }
        match j.nearest_pivot_model {
            Some(d) => {
                by_kind.entry(j.kind.as_str()).or_default().push(d);
                by_kind.entry("**all**").or_default().push(d);
            }
            None => missing += 1,
        }
    }
    let mut out = format!(
        "## Nearest pivot candidate to the true axis line ([0,2] frame)\n\n{missing} rotating joints without candidates.\n\n| kind | joints | within {PIVOT_TARGET_MODEL} | % | median | max |\n|---|---:|---:|---:|---:|---:|\n"
    );
    for (k, ds) in &mut by_kind {
        ds.sort_by(f64::total_cmp);
        let within = ds.iter().filter(|&&d| d <= PIVOT_TARGET_MODEL).count();
        let _ = writeln!(
            out,
            "| {k} | {} | {within} | {} | {:.4} | {:.4} |",
            ds.len(),
            pct(within, ds.len()),
            ds[ds.len() / 2],
            ds[ds.len() - 1]
        );
    }
    out.push('\n');
    out
}

fn time_line(results: &Results) -> String {
    let mut times: Vec<f64> = results
        .iter()
        .filter_map(|(_, r)| r.as_ref().ok().map(|o| o.seconds))
        .collect();
    if times.is_empty() {
        return String::new();
    }
    times.sort_by(f64::total_cmp);
    let mut sweeps: Vec<f64> = joints(results).map(|(_, _, j)| j.sweep_ms).collect();
    sweeps.sort_by(f64::total_cmp);
    let at = |q: f64| sweeps[((sweeps.len() - 1) as f64 * q).round() as usize];
    let mut out = format!(
        "Time per object (ingest, colliders, every sweep and correction): median {:.1} s, max {:.1} s\n",
        times[times.len() / 2],
        times[times.len() - 1]
    );
    if !sweeps.is_empty() {
        let _ = writeln!(
            out,
            "One {}-step sweep per true joint, alone on one thread: median {:.1} ms, p90 {:.1} ms, \
             max {:.1} ms; {} of {} over {SWEEP_TARGET_MS} ms",
            SweepParams::default().steps,
            at(0.5),
            at(0.9),
            at(1.0),
            sweeps.iter().filter(|&&ms| ms > SWEEP_TARGET_MS).count(),
            sweeps.len()
        );
    }
    out
}

/// A joint's motion for the JSON: kind, axis, pivot and limits in the object frame.
fn motion(joint: &Joint) -> serde_json::Value {
    json!({
        "kind": JointKind::as_str(joint.kind),
        "axis": joint.axis_in_object,
        "pivot_m": joint.pivot_in_object_m,
        "limits": joint.limits.map(|l| [l.lower, l.upper]),
    })
}

/// Every joint's outcome as JSON.
pub(crate) fn json(results: &Results) -> serde_json::Value {
    let rows: Vec<serde_json::Value> = joints(results)
        .map(|(name, o, j)| {
            json!({
                "object": name,
                "category": o.category,
                "joint": j.joint,
                "kind": j.kind.as_str(),
                "label": j.label,
                "outcome": format!("{:?}", j.outcome),
                "corrected_wrong": j.corrected_wrong,
                "message": j.message,
                "metrics": j.metrics,
                "nearest_pivot_model": j.nearest_pivot_model,
                "sweep_ms": j.sweep_ms,
                "truth": motion(&j.truth),
                "breakages": j.breakages.iter().map(|b| json!({
                    "breakage": b.breakage.name(),
                    "caught": b.caught,
                    "restored": b.restored,
                    "restored_range": b.restored_range,
                    "message": b.message,
                    "metrics": b.metrics,
                    "corrected": b.corrected.as_ref().map(motion),
                })).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({ "joints": rows })
}
