//! Object-level properties (reference 16.4): permutation-invariant scale ALDE / MnRE from sorted
//! dimensions, mass ALDE / MnRE, plus MAEs and category accuracy as extras.

use crate::common::{RunningMean, abs_error, alde, hit, mnre};
use crate::report::TaskReport;

/// Object-level values, from a prediction (`result`) or the GT (`object_level.volume`, `mass`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObjectValues {
    /// Dimensions (L, W, H in any order); valid only as 3 finite numbers all > 0.
    pub dimensions: Option<Vec<f64>>,
    /// Mass.
    pub mass: Option<f64>,
    /// Object category name.
    pub category: Option<String>,
}

/// One evaluation sample; `pred` is `None` when the prediction is missing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObjectSample {
    /// Predicted values.
    pub pred: Option<ObjectValues>,
    /// Ground-truth values.
    pub gt: ObjectValues,
}

/// The dimensions sorted ascending if they are exactly 3 finite numbers all > 0, else `None`.
#[must_use]
pub fn valid_dimensions(dims: &[f64]) -> Option<[f64; 3]> {
    let mut d: [f64; 3] = dims.try_into().ok()?;
    if !d.iter().all(|v| v.is_finite() && *v > 0.0) {
        return None;
    }
    d.sort_by(f64::total_cmp);
    Some(d)
}

fn mean3(f: impl Fn(usize) -> Option<f64>) -> Option<f64> {
    let mut sum = 0.0;
    for i in 0..3 {
        sum += f(i)?;
    }
    Some(sum / 3.0)
}

fn category(s: &str) -> Option<String> {
    let t = s.trim();
    (!t.is_empty()).then(|| t.to_lowercase())
}

/// Evaluates the object-level task over all samples.
///
/// paper_metrics: `scale_alde`, `scale_mnre`, `mass_alde`, `mass_mnre`; counts: `records`,
/// `missing_prediction`, `scale`, `mass`, `category`; extra: `scale_mae`, `mass_mae`,
/// `category_accuracy`.
#[must_use]
pub fn evaluate_object(samples: &[ObjectSample]) -> TaskReport {
    let mut scale_alde = RunningMean::default();
    let mut scale_mnre = RunningMean::default();
    let mut scale_mae = RunningMean::default();
    let mut mass_alde = RunningMean::default();
    let mut mass_mnre = RunningMean::default();
    let mut mass_mae = RunningMean::default();
    let mut category_acc = RunningMean::default();
    let mut missing_pred = 0_u64;

    for s in samples {
        let Some(p) = &s.pred else {
            missing_pred += 1;
            continue;
        };
        let g = &s.gt;
        let pd = p.dimensions.as_deref().and_then(valid_dimensions);
        let gd = g.dimensions.as_deref().and_then(valid_dimensions);
        if let (Some(pd), Some(gd)) = (pd, gd) {
            scale_alde.push(mean3(|i| alde(pd[i], gd[i])));
            scale_mnre.push(mean3(|i| mnre(pd[i], gd[i])));
            scale_mae.push(mean3(|i| abs_error(pd[i], gd[i])));
        }
        if let (Some(pm), Some(gm)) = (p.mass, g.mass) {
            mass_alde.push(alde(pm, gm));
            mass_mnre.push(mnre(pm, gm));
            mass_mae.push(abs_error(pm, gm));
        }
        let pc = p.category.as_deref().and_then(category);
        let gc = g.category.as_deref().and_then(category);
        if let (Some(pc), Some(gc)) = (pc, gc) {
            category_acc.push(hit(pc == gc));
        }
    }

    let mut report = TaskReport::default();
    report.set_paper("scale_alde", scale_alde.mean());
    report.set_paper("scale_mnre", scale_mnre.mean());
    report.set_paper("mass_alde", mass_alde.mean());
    report.set_paper("mass_mnre", mass_mnre.mean());
    report.set_extra("scale_mae", scale_mae.mean());
    report.set_extra("mass_mae", mass_mae.mean());
    report.set_extra("category_accuracy", category_acc.mean());
    report.set_count("records", samples.len() as u64);
    report.set_count("missing_prediction", missing_pred);
    report.set_count("scale", scale_alde.count());
    report.set_count("mass", mass_alde.count());
    report.set_count("category", category_acc.count());
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::common::close;

    fn values(dims: &[f64], mass: f64, category: &str) -> ObjectValues {
        ObjectValues {
            dimensions: Some(dims.to_vec()),
            mass: Some(mass),
            category: Some(category.to_owned()),
        }
    }

    fn sample(pred: ObjectValues, gt: ObjectValues) -> ObjectSample {
        ObjectSample {
            pred: Some(pred),
            gt,
        }
    }

    #[test]
    fn dimensions_need_three_finite_positive_numbers_and_are_sorted() {
        assert_eq!(valid_dimensions(&[3.0, 1.0, 2.0]), Some([1.0, 2.0, 3.0]));
        assert_eq!(valid_dimensions(&[1.0, 2.0]), None);
        assert_eq!(valid_dimensions(&[1.0, 2.0, 3.0, 4.0]), None);
        assert_eq!(valid_dimensions(&[1.0, 0.0, 3.0]), None);
        assert_eq!(valid_dimensions(&[1.0, f64::NAN, 3.0]), None);
    }

    #[test]
    fn permuted_dimensions_have_zero_scale_alde_and_unit_mnre() {
        let r = evaluate_object(&[sample(
            values(&[1.0, 2.0, 3.0], 1.0, "a"),
            values(&[3.0, 2.0, 1.0], 1.0, "a"),
        )]);
        assert!(close(r.paper("scale_alde"), 0.0));
        assert!(close(r.paper("scale_mnre"), 1.0));
        assert!(close(r.extra("scale_mae"), 0.0));
    }

    #[test]
    fn scale_metrics_average_over_sorted_dimensions() {
        // Sorted pred [2,2,3] vs GT [1,2,3]: ALDE (ln2+0+0)/3, MnRE (0.5+1+1)/3, MAE 1/3.
        let r = evaluate_object(&[sample(
            values(&[3.0, 2.0, 2.0], 1.0, "a"),
            values(&[1.0, 2.0, 3.0], 1.0, "a"),
        )]);
        assert!(close(r.paper("scale_alde"), 2f64.ln() / 3.0));
        assert!(close(r.paper("scale_mnre"), 2.5 / 3.0));
        assert!(close(r.extra("scale_mae"), 1.0 / 3.0));
    }

    #[test]
    fn mass_alde_mnre_and_mae_are_hand_computed() {
        let r = evaluate_object(&[sample(
            values(&[1.0, 1.0, 1.0], 2.0, "a"),
            values(&[1.0, 1.0, 1.0], 1.0, "a"),
        )]);
        assert!(close(r.paper("mass_alde"), 2f64.ln()));
        assert!(close(r.paper("mass_mnre"), 0.5));
        assert!(close(r.extra("mass_mae"), 1.0));
    }

    #[test]
    fn invalid_dimensions_and_zero_mass_are_excluded() {
        let r = evaluate_object(&[sample(
            values(&[1.0, -1.0, 1.0], 0.0, "a"),
            values(&[1.0, 1.0, 1.0], 1.0, "a"),
        )]);
        assert_eq!(r.paper("scale_alde"), None);
        assert_eq!(r.paper("mass_alde"), None);
        assert_eq!(r.paper("mass_mnre"), None);
        assert_eq!(r.count("scale"), 0);
        assert_eq!(r.count("mass"), 0);
    }

    #[test]
    fn category_accuracy_is_stripped_case_insensitive_exact_match() {
        let r = evaluate_object(&[
            sample(
                values(&[1.0, 1.0, 1.0], 1.0, " Chair "),
                values(&[1.0, 1.0, 1.0], 1.0, "chair"),
            ),
            sample(
                values(&[1.0, 1.0, 1.0], 1.0, "chairs"),
                values(&[1.0, 1.0, 1.0], 1.0, "chair"),
            ),
        ]);
        assert!(close(r.extra("category_accuracy"), 0.5));
    }

    #[test]
    fn missing_prediction_is_counted_and_excluded() {
        let r = evaluate_object(&[
            ObjectSample {
                pred: None,
                gt: values(&[1.0, 1.0, 1.0], 1.0, "a"),
            },
            sample(
                values(&[1.0, 1.0, 1.0], 1.0, "a"),
                values(&[1.0, 1.0, 1.0], 1.0, "a"),
            ),
        ]);
        assert_eq!(r.count("missing_prediction"), 1);
        assert_eq!(r.count("mass"), 1);
        assert!(close(r.paper("mass_mnre"), 1.0));
    }
}
