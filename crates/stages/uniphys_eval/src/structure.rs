//! Articulation structure (reference 16.2): member sets compared by IoU and precision / recall /
//! F1, micro and macro.

use serde_json::Value;

use crate::common::{RunningMean, hit};
use crate::member_ids::{IdSet, normalise_id_set};
use crate::report::TaskReport;

/// One evaluation sample: the predicted `members` and the GT `dependency` lists, as raw JSON.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StructureSample {
    /// Predicted member ids (`result.members`); `None` when absent.
    pub pred: Option<Value>,
    /// Ground-truth member ids (`motion_info.dependency`); `None` when absent.
    pub gt: Option<Value>,
}

/// IoU `|P ∩ G| / |P ∪ G|` of two sets, 1.0 when both are empty.
#[must_use]
pub fn set_iou(pred: &IdSet, gt: &IdSet) -> f64 {
    let union = pred.union(gt).count();
    if union == 0 {
        return 1.0;
    }
    let inter = pred.intersection(gt).count();
    ratio(inter as u64, union as u64)
}

fn ratio(num: u64, den: u64) -> f64 {
    num as f64 / den as f64
}

/// Precision, recall and F1 from counts with the edge rules of 16.2: precision is
/// `1 if FN == 0 else 0` when nothing is predicted; recall is 1 when nothing is expected; F1 is
/// 0 when `P + R = 0`.
fn prf(tp: u64, fp: u64, fn_: u64) -> (f64, f64, f64) {
    let precision = if tp + fp == 0 {
        if fn_ == 0 { 1.0 } else { 0.0 }
    } else {
        ratio(tp, tp + fp)
    };
    let recall = if tp + fn_ == 0 {
        1.0
    } else {
        ratio(tp, tp + fn_)
    };
    let f1 = if precision + recall == 0.0 {
        0.0
    } else {
        2.0 * precision * recall / (precision + recall)
    };
    (precision, recall, f1)
}

/// Evaluates the articulation-structure task over all samples.
///
/// paper_metrics: `structure_miou`, `structure_micro_f1`; counts: `records`, `missing_pair`,
/// `pairs`; extra: `micro_precision`, `micro_recall`, `macro_precision`, `macro_recall`,
/// `macro_f1`, `exact_match_rate`.
#[must_use]
pub fn evaluate_structure(samples: &[StructureSample]) -> TaskReport {
    let mut iou = RunningMean::default();
    let (mut macro_p, mut macro_r, mut macro_f) = (
        RunningMean::default(),
        RunningMean::default(),
        RunningMean::default(),
    );
    let mut exact = RunningMean::default();
    let (mut tp, mut fp, mut fn_) = (0_u64, 0_u64, 0_u64);
    let mut missing_pair = 0_u64;

    for s in samples {
        let pair = match (&s.pred, &s.gt) {
            (Some(p), Some(g)) => normalise_id_set(p).ok().zip(normalise_id_set(g).ok()),
            _ => None,
        };
        let Some((p, g)) = pair else {
            missing_pair += 1;
            continue;
        };
        let s_tp = p.intersection(&g).count() as u64;
        let s_fp = p.len() as u64 - s_tp;
        let s_fn = g.len() as u64 - s_tp;
        tp += s_tp;
        fp += s_fp;
        fn_ += s_fn;
        iou.push(Some(set_iou(&p, &g)));
        let (sp, sr, sf) = prf(s_tp, s_fp, s_fn);
        macro_p.push(Some(sp));
        macro_r.push(Some(sr));
        macro_f.push(Some(sf));
        exact.push(hit(p == g));
    }

    let micro = (iou.count() > 0).then(|| prf(tp, fp, fn_));
    let mut report = TaskReport::default();
    report.set_paper("structure_miou", iou.mean());
    report.set_paper("structure_micro_f1", micro.map(|m| m.2));
    report.set_extra("micro_precision", micro.map(|m| m.0));
    report.set_extra("micro_recall", micro.map(|m| m.1));
    report.set_extra("macro_precision", macro_p.mean());
    report.set_extra("macro_recall", macro_r.mean());
    report.set_extra("macro_f1", macro_f.mean());
    report.set_extra("exact_match_rate", exact.mean());
    report.set_count("records", samples.len() as u64);
    report.set_count("missing_pair", missing_pair);
    report.set_count("pairs", iou.count());
    report
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    use crate::common::close;

    fn sample(pred: Value, gt: Value) -> StructureSample {
        StructureSample {
            pred: Some(pred),
            gt: Some(gt),
        }
    }

    #[test]
    fn empty_sets_have_iou_one() {
        assert!(close(Some(set_iou(&IdSet::new(), &IdSet::new())), 1.0));
    }

    #[test]
    fn set_iou_is_intersection_over_union() {
        let p = normalise_id_set(&json!([1, 2, 3])).expect("valid");
        let g = normalise_id_set(&json!([2, 3, 4])).expect("valid");
        assert!(close(Some(set_iou(&p, &g)), 0.5));
    }

    #[test]
    fn micro_f1_with_two_tp_one_fp_one_fn_is_two_thirds() {
        let r = evaluate_structure(&[sample(json!([1, 2, 3]), json!([1, 2, 4]))]);
        assert!(close(r.paper("structure_micro_f1"), 2.0 / 3.0));
        assert!(close(r.extra("micro_precision"), 2.0 / 3.0));
        assert!(close(r.extra("micro_recall"), 2.0 / 3.0));
        assert!(close(r.paper("structure_miou"), 0.5));
        assert!(close(r.extra("exact_match_rate"), 0.0));
    }

    #[test]
    fn micro_counts_are_summed_across_samples() {
        // TP=2, FP=1, FN=0 then TP=0, FP=0, FN=1 -> TP=2, FP=1, FN=1.
        let r = evaluate_structure(&[
            sample(json!([1, 2, 3]), json!([1, 2])),
            sample(json!([]), json!([7])),
        ]);
        assert!(close(r.paper("structure_micro_f1"), 2.0 / 3.0));
        // IoU 2/3 and 0 -> mean 1/3.
        assert!(close(r.paper("structure_miou"), 1.0 / 3.0));
    }

    #[test]
    fn invalid_or_absent_sets_are_excluded_as_missing_pair() {
        let r = evaluate_structure(&[
            sample(json!([1, true]), json!([1])),
            StructureSample {
                pred: None,
                gt: Some(json!([1])),
            },
            sample(json!([1]), json!([1])),
        ]);
        assert_eq!(r.count("records"), 3);
        assert_eq!(r.count("missing_pair"), 2);
        assert_eq!(r.count("pairs"), 1);
        assert!(close(r.paper("structure_miou"), 1.0));
        assert!(close(r.extra("exact_match_rate"), 1.0));
    }

    #[test]
    fn nothing_predicted_with_nonempty_gt_has_zero_precision_and_f1() {
        let r = evaluate_structure(&[sample(json!([]), json!([1]))]);
        assert!(close(r.extra("micro_precision"), 0.0));
        assert!(close(r.extra("micro_recall"), 0.0));
        assert!(close(r.paper("structure_micro_f1"), 0.0));
        assert!(close(r.extra("macro_precision"), 0.0));
    }

    #[test]
    fn both_empty_gives_perfect_scores() {
        let r = evaluate_structure(&[sample(json!([]), json!([]))]);
        assert!(close(r.paper("structure_miou"), 1.0));
        assert!(close(r.paper("structure_micro_f1"), 1.0));
        assert!(close(r.extra("macro_f1"), 1.0));
        assert!(close(r.extra("exact_match_rate"), 1.0));
    }

    #[test]
    fn predictions_against_empty_gt_have_recall_one_and_zero_precision() {
        let r = evaluate_structure(&[sample(json!([1]), json!([]))]);
        assert!(close(r.extra("macro_precision"), 0.0));
        assert!(close(r.extra("macro_recall"), 1.0));
        assert!(close(r.extra("macro_f1"), 0.0));
    }

    #[test]
    fn macro_averages_per_sample_scores() {
        // Sample 1: P=1, R=1/2, F1=2/3. Sample 2: P=R=F1=1.
        let r = evaluate_structure(&[
            sample(json!([1]), json!([1, 2])),
            sample(json!(["a"]), json!(["a"])),
        ]);
        assert!(close(r.extra("macro_precision"), 1.0));
        assert!(close(r.extra("macro_recall"), 0.75));
        assert!(close(r.extra("macro_f1"), (2.0 / 3.0 + 1.0) / 2.0));
        assert!(close(r.extra("exact_match_rate"), 0.5));
    }

    #[test]
    fn no_valid_pairs_reports_no_metrics() {
        let r = evaluate_structure(&[StructureSample::default()]);
        assert_eq!(r.paper("structure_miou"), None);
        assert_eq!(r.paper("structure_micro_f1"), None);
    }
}
