//! Kinematic parameters (reference 16.1): joint type accuracy, axis angular error, pivot distance
//! to the GT axis line and limit mIoU.

use crate::common::{RunningMean, hit};
use crate::kinematic_measures::{axis_angular_error_degrees, interval_iou, point_to_line_distance};
use crate::report::TaskReport;
/// Axis accuracy threshold of the extra metric, in degrees.
const AXIS_ACCURACY_DEG: f64 = 10.0;

/// One parsed joint prediction; any field may be missing or unparseable (`None`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JointPrediction {
    /// Predicted movement type letter (`B` prismatic, `C` revolute).
    pub motion_type: Option<char>,
    /// Predicted axis direction (any length, any sign).
    pub axis: Option<[f64; 3]>,
    /// Predicted pivot in the `[0, 2]` model frame.
    pub pivot_model: Option<[f64; 3]>,
    /// Predicted range: radians for `C`, source units for `B`.
    pub range: Option<[f64; 2]>,
}

/// One evaluation sample: ground truth and the (optional) prediction.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KinematicSample {
    /// Ground-truth movement type; anything but `B`/`C` (or `None`) excludes the sample.
    pub gt_type: Option<char>,
    /// The prediction; `None` (unparseable or error record) counts as a wrong joint type.
    pub pred: Option<JointPrediction>,
    /// Ground-truth axis direction.
    pub gt_axis: Option<[f64; 3]>,
    /// Ground-truth pivot in the `[0, 2]` model frame.
    pub gt_pivot_model: Option<[f64; 3]>,
    /// Ground-truth range: radians for `C`, source units for `B`.
    pub gt_range: Option<[f64; 2]>,
    /// Scale of the saved coordinate frame; `B` ranges are divided by it (skipped without it).
    pub frame_scale: Option<f64>,
}

fn scaled(range: [f64; 2], scale: f64) -> [f64; 2] {
    [range[0] / scale, range[1] / scale]
}

/// Evaluates the kinematic-parameter task over all samples.
///
/// paper_metrics: `joint_type_accuracy`, `axis_angular_error_degrees`,
/// `pivot_distance_error_aabb_0_2`, `limit_miou`; counts: `records`, `missing_source_sample`,
/// `missing_prediction`, `missing_coordinate_frame` (B limit pairs skipped for lack of a scale),
/// `joint_type`, `axis`, `pivot`, `limit`; extra: `axis_accuracy_10deg`.
#[must_use]
pub fn evaluate_kinematics(samples: &[KinematicSample]) -> TaskReport {
    let mut type_acc = RunningMean::default();
    let mut axis_err = RunningMean::default();
    let mut axis_acc = RunningMean::default();
    let mut pivot_err = RunningMean::default();
    let mut limit_iou = RunningMean::default();
    let (mut missing_gt, mut missing_pred, mut missing_frame) = (0_u64, 0_u64, 0_u64);

    for s in samples {
        let gt_type = match s.gt_type {
            Some(t @ ('B' | 'C')) => t,
            _ => {
                missing_gt += 1;
                continue;
            }
        };
        let Some(pred) = s.pred else {
            missing_pred += 1;
            type_acc.push(hit(false));
            continue;
        };
        let correct = pred.motion_type == Some(gt_type);
        type_acc.push(hit(correct));
        if !correct {
            continue;
        }
        if let (Some(a), Some(g)) = (pred.axis, s.gt_axis)
            && let Some(err) = axis_angular_error_degrees(a, g)
        {
            axis_err.push(Some(err));
            axis_acc.push(hit(err < AXIS_ACCURACY_DEG));
        }
        if gt_type == 'C'
            && let (Some(p), Some(pg), Some(g)) = (pred.pivot_model, s.gt_pivot_model, s.gt_axis)
        {
            pivot_err.push(point_to_line_distance(p, pg, g));
        }
        if let (Some(pr), Some(gr)) = (pred.range, s.gt_range) {
            let pair = if gt_type == 'B' {
                match s.frame_scale.filter(|v| v.is_finite() && *v > 0.0) {
                    Some(scale) => Some((scaled(pr, scale), scaled(gr, scale))),
                    None => {
                        missing_frame += 1;
                        None
                    }
                }
            } else {
                Some((pr, gr))
            };
            if let Some((pr, gr)) = pair {
                limit_iou.push(interval_iou(pr, gr));
            }
        }
    }

    let mut report = TaskReport::default();
    report.set_paper("joint_type_accuracy", type_acc.mean());
    report.set_paper("axis_angular_error_degrees", axis_err.mean());
    report.set_paper("pivot_distance_error_aabb_0_2", pivot_err.mean());
    report.set_paper("limit_miou", limit_iou.mean());
    report.set_extra("axis_accuracy_10deg", axis_acc.mean());
    report.set_count("records", samples.len() as u64);
    report.set_count("missing_source_sample", missing_gt);
    report.set_count("missing_prediction", missing_pred);
    report.set_count("missing_coordinate_frame", missing_frame);
    report.set_count("joint_type", type_acc.count());
    report.set_count("axis", axis_err.count());
    report.set_count("pivot", pivot_err.count());
    report.set_count("limit", limit_iou.count());
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = 1e-9;

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < EPS)
    }

    fn revolute_sample() -> KinematicSample {
        KinematicSample {
            gt_type: Some('C'),
            pred: Some(JointPrediction {
                motion_type: Some('C'),
                axis: Some([0.0, 0.0, -2.0]),
                pivot_model: Some([1.0, 1.0, 5.0]),
                range: Some([0.0, 1.0]),
            }),
            gt_axis: Some([0.0, 0.0, 1.0]),
            gt_pivot_model: Some([0.0, 0.0, 0.0]),
            gt_range: Some([0.5, 2.0]),
            frame_scale: None,
        }
    }

    #[test]
    fn all_metrics_for_a_correct_revolute_sample() {
        let r = evaluate_kinematics(&[revolute_sample()]);
        assert!(close(r.paper("joint_type_accuracy"), 1.0));
        assert!(close(r.paper("axis_angular_error_degrees"), 0.0));
        assert!(close(r.paper("pivot_distance_error_aabb_0_2"), 2f64.sqrt()));
        assert!(close(r.paper("limit_miou"), 0.25));
        assert!(close(r.extra("axis_accuracy_10deg"), 1.0));
        assert_eq!(r.count("records"), 1);
        assert_eq!(r.count("axis"), 1);
        assert_eq!(r.count("pivot"), 1);
        assert_eq!(r.count("limit"), 1);
    }

    #[test]
    fn missing_prediction_counts_as_wrong_type_and_gtless_samples_are_excluded() {
        let good = revolute_sample();
        let missing = KinematicSample { pred: None, ..good };
        let no_gt = KinematicSample {
            gt_type: None,
            ..good
        };
        let other_gt = KinematicSample {
            gt_type: Some('D'),
            ..good
        };
        let r = evaluate_kinematics(&[good, missing, no_gt, other_gt]);
        assert!(close(r.paper("joint_type_accuracy"), 0.5));
        assert_eq!(r.count("records"), 4);
        assert_eq!(r.count("missing_source_sample"), 2);
        assert_eq!(r.count("missing_prediction"), 1);
        assert_eq!(r.count("joint_type"), 2);
        assert_eq!(r.count("axis"), 1);
    }

    #[test]
    fn wrong_type_skips_axis_pivot_and_limit() {
        let mut s = revolute_sample();
        if let Some(p) = s.pred.as_mut() {
            p.motion_type = Some('B');
        }
        let r = evaluate_kinematics(&[s]);
        assert!(close(r.paper("joint_type_accuracy"), 0.0));
        assert_eq!(r.paper("axis_angular_error_degrees"), None);
        assert_eq!(r.paper("pivot_distance_error_aabb_0_2"), None);
        assert_eq!(r.paper("limit_miou"), None);
        assert_eq!(r.count("axis"), 0);
    }

    #[test]
    fn axis_accuracy_counts_errors_below_ten_degrees() {
        let mut far = revolute_sample();
        if let Some(p) = far.pred.as_mut() {
            p.axis = Some([1.0, 0.0, 0.0]);
        }
        let r = evaluate_kinematics(&[revolute_sample(), far]);
        assert!(close(r.paper("axis_angular_error_degrees"), 45.0));
        assert!(close(r.extra("axis_accuracy_10deg"), 0.5));
    }

    #[test]
    fn prismatic_has_no_pivot_and_scales_ranges_or_skips_without_scale() {
        let base = revolute_sample();
        let pred = base.pred.map(|p| JointPrediction {
            motion_type: Some('B'),
            ..p
        });
        let with_scale = KinematicSample {
            gt_type: Some('B'),
            pred,
            frame_scale: Some(2.0),
            ..base
        };
        let without_scale = KinematicSample {
            frame_scale: None,
            ..with_scale
        };
        let r = evaluate_kinematics(&[with_scale, without_scale]);
        assert_eq!(r.paper("pivot_distance_error_aabb_0_2"), None);
        assert!(close(r.paper("limit_miou"), 0.25));
        assert_eq!(r.count("limit"), 1);
        assert_eq!(r.count("missing_coordinate_frame"), 1);
    }

    #[test]
    fn empty_input_reports_no_metrics() {
        let r = evaluate_kinematics(&[]);
        assert_eq!(r.paper("joint_type_accuracy"), None);
        assert_eq!(r.count("records"), 0);
    }
}
