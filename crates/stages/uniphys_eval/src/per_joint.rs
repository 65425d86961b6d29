//! Joint by joint: each ground-truth movable joint next to the predicted joint of the same
//! child part, with the paper's measures for that one joint, so errors can be read one by one.

use std::fmt::Write as _;

use serde::Serialize;

use crate::annotated::{AnnotatedAsset, AnnotatedJoint};
use crate::kinematic_measures::{axis_angular_error_degrees, interval_iou, point_to_line_distance};
use crate::pairing::pair_samples;

/// One ground-truth movable joint and what was predicted for its child part.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointComparison {
    /// The asset, as the caller names it.
    pub asset: String,
    /// The child part the joint moves.
    pub part: String,
    /// Ground-truth kind: `prismatic`, `revolute` or `continuous`.
    pub gt_kind: &'static str,
    /// Predicted kind: also `fixed`, or `none` when the part has no predicted joint.
    pub predicted_kind: &'static str,
    /// Axis angular error, degrees, sign ignored; only when the type is right.
    pub axis_error_deg: Option<f64>,
    /// Distance from the predicted pivot to the true axis line in the [0,2] frame; rotating
    /// joints of the right type only.
    pub pivot_error: Option<f64>,
    /// Ground-truth range: radians, or the [0,2] frame's units for slides.
    pub gt_range: Option<[f64; 2]>,
    /// Predicted range in the same units; only when the type is right.
    pub predicted_range: Option<[f64; 2]>,
    /// IoU of the two ranges; only when the type is right.
    pub limit_iou: Option<f64>,
}

/// Kind of an annotated joint as a word: `B` is a slide, `C` a turn (a full-turn range is read as
/// continuous), `D` fixed; `none` when the part has no joint.
#[must_use]
pub fn joint_kind_word(joint: Option<&AnnotatedJoint>) -> &'static str {
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

/// Every ground-truth movable joint of `gt` next to the joint `pred` gives its child part; rows
/// name the asset `asset`.
#[must_use]
pub fn compare_joints(
    asset: &str,
    pred: &AnnotatedAsset,
    gt: &AnnotatedAsset,
) -> Vec<JointComparison> {
    let samples = pair_samples(pred, gt);
    gt.joints
        .iter()
        .filter(|j| j.is_movable())
        .zip(&samples.kinematics)
        .map(|(g, sample)| {
            let p = pred.joint_of(&g.child);
            let same_type = p.is_some_and(|p| p.motion_type == g.motion_type);
            let prediction = sample.pred.as_ref().filter(|_| same_type);
            let axis_error_deg = prediction
                .and_then(|p| p.axis)
                .and_then(|a| axis_angular_error_degrees(a, g.axis));
            let pivot_error = prediction.filter(|_| g.motion_type == 'C').and_then(|p| {
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
            let predicted_range = scaled(sample.pred.as_ref().and_then(|p| p.range));
            let limit_iou = prediction.and_then(|_| interval_iou(predicted_range?, gt_range?));
            JointComparison {
                asset: asset.to_owned(),
                part: g.child.clone(),
                gt_kind: joint_kind_word(Some(g)),
                predicted_kind: joint_kind_word(p),
                axis_error_deg,
                pivot_error,
                gt_range,
                predicted_range: predicted_range.filter(|_| same_type),
                limit_iou,
            }
        })
        .collect()
}

/// The comparisons as a Markdown table.
#[must_use]
pub fn per_joint_table(rows: &[JointComparison]) -> String {
    let cell = |v: Option<f64>, decimals: usize| {
        v.map_or_else(|| "-".to_owned(), |v| format!("{v:.decimals$}"))
    };
    let range = |r: Option<[f64; 2]>| {
        r.map_or_else(|| "-".to_owned(), |[lo, hi]| format!("[{lo:.2}, {hi:.2}]"))
    };
    let mut out = String::from(
        "| asset | part | GT | predicted | axis err (°) | pivot err | GT range | predicted range | limit IoU |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.asset,
            r.part,
            r.gt_kind,
            r.predicted_kind,
            cell(r.axis_error_deg, 1),
            cell(r.pivot_error, 3),
            range(r.gt_range),
            range(r.predicted_range),
            cell(r.limit_iou, 2)
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint(child: &str, motion_type: char, axis: [f64; 3], range: [f64; 2]) -> AnnotatedJoint {
        AnnotatedJoint {
            child: child.to_owned(),
            motion_type,
            axis,
            pivot_in_object: Some([0.0, 0.0, 0.0]),
            range: Some(range),
            members: vec![child.to_owned()],
        }
    }

    fn asset(joints: Vec<AnnotatedJoint>) -> AnnotatedAsset {
        AnnotatedAsset {
            origin: "test".to_owned(),
            bounds_in_object: Some([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]),
            joints,
            ..AnnotatedAsset::default()
        }
    }

    #[test]
    fn each_true_joint_is_listed_with_its_own_errors() {
        let gt = asset(vec![
            joint("door", 'C', [0.0, 0.0, 1.0], [0.0, 1.5]),
            joint("drawer", 'B', [1.0, 0.0, 0.0], [0.0, 0.5]),
            joint("knob", 'C', [0.0, 1.0, 0.0], [0.0, std::f64::consts::TAU]),
            joint("body", 'D', [0.0, 0.0, 1.0], [0.0, 0.0]),
        ]);
        let pred = asset(vec![
            // The door's axis a quarter turn off, the drawer turned instead of slid, no knob.
            joint("door", 'C', [1.0, 0.0, 0.0], [0.0, 1.5]),
            joint("drawer", 'C', [1.0, 0.0, 0.0], [0.0, 1.0]),
        ]);
        let rows = compare_joints("cabinet", &pred, &gt);
        assert_eq!(rows.len(), 3, "movable joints only: {rows:#?}");
        let door = &rows[0];
        assert_eq!(
            (door.gt_kind, door.predicted_kind),
            ("revolute", "revolute")
        );
        assert!((door.axis_error_deg.expect("same type") - 90.0).abs() < 1e-6);
        assert!((door.limit_iou.expect("same type") - 1.0).abs() < 1e-9);
        let drawer = &rows[1];
        assert_eq!(
            (drawer.gt_kind, drawer.predicted_kind),
            ("prismatic", "revolute")
        );
        assert_eq!(drawer.axis_error_deg, None, "no axis error across types");
        assert_eq!(drawer.predicted_range, None);
        let knob = &rows[2];
        assert_eq!((knob.gt_kind, knob.predicted_kind), ("continuous", "none"));
        assert!(rows.iter().all(|r| r.asset == "cabinet"));
        let table = per_joint_table(&rows);
        assert!(
            table.contains("| cabinet | door | revolute | revolute | 90.0 |"),
            "{table}"
        );
    }
}
