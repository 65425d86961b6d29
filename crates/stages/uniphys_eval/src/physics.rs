//! Part-level intrinsic physics (reference 16.3): material category accuracy, density ALDE,
//! friction and affordance MAE, plus Young's modulus / hardness ALDE, Poisson MAE and graspable
//! accuracy as extras.

use crate::common::{RunningMean, abs_error, alde, hit};
use crate::report::TaskReport;

/// Physical properties of one part, as parsed from a prediction or from the ground truth; an
/// absent or unparseable field is `None`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PhysicalProperties {
    /// Material label, e.g. `"Metal/Steel"`; only the category before the first `/` is compared.
    pub material: Option<String>,
    /// Density in the units stored (g/cm^3 on both sides).
    pub density: Option<f64>,
    /// Friction coefficient.
    pub friction: Option<f64>,
    /// Affordance score (GT from `part_level.affordance`).
    pub affordance: Option<f64>,
    /// Young's modulus (same units on both sides).
    pub young: Option<f64>,
    /// Hardness (same units on both sides).
    pub hardness: Option<f64>,
    /// Poisson's ratio.
    pub poisson: Option<f64>,
    /// Whether the part is graspable (GT from `part_level.graspable`); real booleans only.
    pub graspable: Option<bool>,
}

/// One evaluation sample; `pred` is `None` when the prediction is not a mapping.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PhysicsSample {
    /// Predicted properties (`result.physical_properties`).
    pub pred: Option<PhysicalProperties>,
    /// Ground-truth properties (`basic_info` + `part_level`).
    pub gt: PhysicalProperties,
}

/// Material category: the text before the first `/`, stripped and lower-cased; `None` if empty.
#[must_use]
pub fn material_category(label: &str) -> Option<String> {
    let head = label.split_once('/').map_or(label, |(head, _)| head).trim();
    (!head.is_empty()).then(|| head.to_lowercase())
}

fn both<T: Copy>(p: Option<T>, g: Option<T>) -> Option<(T, T)> {
    p.zip(g)
}

/// Evaluates the part-level physics task over all samples.
///
/// paper_metrics: `material_accuracy`, `density_alde`, `friction_mae`, `affordance_mae`;
/// counts: `records`, `missing_prediction` and one count per metric; extra: `young_alde`,
/// `hardness_alde`, `poisson_mae`, `graspable_accuracy`.
#[must_use]
pub fn evaluate_physics(samples: &[PhysicsSample]) -> TaskReport {
    let mut material = RunningMean::default();
    let mut density = RunningMean::default();
    let mut friction = RunningMean::default();
    let mut affordance = RunningMean::default();
    let mut young = RunningMean::default();
    let mut hardness = RunningMean::default();
    let mut poisson = RunningMean::default();
    let mut graspable = RunningMean::default();
    let mut missing_pred = 0_u64;

    for s in samples {
        let Some(p) = &s.pred else {
            missing_pred += 1;
            continue;
        };
        let g = &s.gt;
        let pm = p.material.as_deref().and_then(material_category);
        let gm = g.material.as_deref().and_then(material_category);
        if let (Some(pm), Some(gm)) = (pm, gm) {
            material.push(hit(pm == gm));
        }
        density.push(both(p.density, g.density).and_then(|(p, g)| alde(p, g)));
        friction.push(both(p.friction, g.friction).and_then(|(p, g)| abs_error(p, g)));
        affordance.push(both(p.affordance, g.affordance).and_then(|(p, g)| abs_error(p, g)));
        young.push(both(p.young, g.young).and_then(|(p, g)| alde(p, g)));
        hardness.push(both(p.hardness, g.hardness).and_then(|(p, g)| alde(p, g)));
        poisson.push(both(p.poisson, g.poisson).and_then(|(p, g)| abs_error(p, g)));
        if let Some((p, g)) = both(p.graspable, g.graspable) {
            graspable.push(hit(p == g));
        }
    }

    let mut report = TaskReport::default();
    report.set_paper("material_accuracy", material.mean());
    report.set_paper("density_alde", density.mean());
    report.set_paper("friction_mae", friction.mean());
    report.set_paper("affordance_mae", affordance.mean());
    report.set_extra("young_alde", young.mean());
    report.set_extra("hardness_alde", hardness.mean());
    report.set_extra("poisson_mae", poisson.mean());
    report.set_extra("graspable_accuracy", graspable.mean());
    report.set_count("records", samples.len() as u64);
    report.set_count("missing_prediction", missing_pred);
    for (name, m) in [
        ("material", material),
        ("density", density),
        ("friction", friction),
        ("affordance", affordance),
        ("young", young),
        ("hardness", hardness),
        ("poisson", poisson),
        ("graspable", graspable),
    ] {
        report.set_count(name, m.count());
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::common::close;

    fn props(material: &str, density: f64, friction: f64) -> PhysicalProperties {
        PhysicalProperties {
            material: Some(material.to_owned()),
            density: Some(density),
            friction: Some(friction),
            affordance: Some(0.5),
            young: Some(200.0),
            hardness: Some(10.0),
            poisson: Some(0.3),
            graspable: Some(true),
        }
    }

    #[test]
    fn material_category_is_prefix_before_slash_stripped_and_lowercased() {
        assert_eq!(material_category(" Metal /Steel"), Some("metal".to_owned()));
        assert_eq!(material_category("WOOD"), Some("wood".to_owned()));
        assert_eq!(material_category("  /x"), None);
    }

    #[test]
    fn material_accuracy_compares_categories_and_skips_missing_sides() {
        let mut no_material = props("x", 1.0, 0.1);
        no_material.material = None;
        let samples = [
            PhysicsSample {
                pred: Some(props("metal/steel", 1.0, 0.1)),
                gt: props("Metal/Aluminium", 1.0, 0.1),
            },
            PhysicsSample {
                pred: Some(props("wood", 1.0, 0.1)),
                gt: props("plastic/abs", 1.0, 0.1),
            },
            PhysicsSample {
                pred: Some(no_material),
                gt: props("wood", 1.0, 0.1),
            },
        ];
        let r = evaluate_physics(&samples);
        assert!(close(r.paper("material_accuracy"), 0.5));
        assert_eq!(r.count("material"), 2);
    }

    #[test]
    fn density_alde_and_friction_mae_are_hand_computed() {
        let samples = [
            PhysicsSample {
                pred: Some(props("a", 2.0, 0.2)),
                gt: props("a", 1.0, 0.5),
            },
            PhysicsSample {
                pred: Some(props("a", 1.0, 0.6)),
                gt: props("a", 1.0, 0.5),
            },
        ];
        let r = evaluate_physics(&samples);
        // ALDE: (ln 2 + 0) / 2; MAE: (0.3 + 0.1) / 2.
        assert!(close(r.paper("density_alde"), 2f64.ln() / 2.0));
        assert!((r.paper("friction_mae").expect("two pairs") - 0.2).abs() < 1e-9);
        assert!(close(r.paper("affordance_mae"), 0.0));
    }

    #[test]
    fn non_positive_density_is_excluded_from_alde() {
        let samples = [
            PhysicsSample {
                pred: Some(props("a", 0.0, 0.2)),
                gt: props("a", 1.0, 0.2),
            },
            PhysicsSample {
                pred: Some(props("a", 2.0, 0.2)),
                gt: props("a", 1.0, 0.2),
            },
        ];
        let r = evaluate_physics(&samples);
        assert!(close(r.paper("density_alde"), 2f64.ln()));
        assert_eq!(r.count("density"), 1);
    }

    #[test]
    fn missing_prediction_is_excluded_not_penalised() {
        let samples = [
            PhysicsSample {
                pred: None,
                gt: props("a", 1.0, 0.2),
            },
            PhysicsSample {
                pred: Some(props("a", 1.0, 0.2)),
                gt: props("a", 1.0, 0.2),
            },
        ];
        let r = evaluate_physics(&samples);
        assert_eq!(r.count("missing_prediction"), 1);
        assert!(close(r.paper("material_accuracy"), 1.0));
        assert_eq!(r.count("material"), 1);
    }

    #[test]
    fn extras_young_hardness_poisson_and_graspable() {
        let mut pred = props("a", 1.0, 0.2);
        pred.young = Some(100.0);
        pred.hardness = Some(10.0 * std::f64::consts::E);
        pred.poisson = Some(0.4);
        pred.graspable = Some(false);
        let r = evaluate_physics(&[PhysicsSample {
            pred: Some(pred),
            gt: props("a", 1.0, 0.2),
        }]);
        assert!(close(r.extra("young_alde"), 2f64.ln()));
        assert!((r.extra("hardness_alde").expect("pair") - 1.0).abs() < 1e-9);
        assert!((r.extra("poisson_mae").expect("pair") - 0.1).abs() < 1e-9);
        assert!(close(r.extra("graspable_accuracy"), 0.0));
    }

    #[test]
    fn graspable_needs_both_booleans_and_nan_values_are_ignored() {
        let mut pred = props("a", f64::NAN, 0.2);
        pred.graspable = None;
        let r = evaluate_physics(&[PhysicsSample {
            pred: Some(pred),
            gt: props("a", 1.0, 0.2),
        }]);
        assert_eq!(r.extra("graspable_accuracy"), None);
        assert_eq!(r.paper("density_alde"), None);
        assert_eq!(r.count("graspable"), 0);
    }
}
