//! Intrinsic verification (reference 11.3, with hardness checked against the prior too): per
//! part levels 0-3, per object level 4 (mass against density times volume), and the object's
//! plausibility against real objects of its kind (warnings).

use std::collections::BTreeMap;

use uniphys_geometry::{Aabb, DVec3};
use uniphys_types::{AssetRecord, CheckOutcome, CheckResult, PartRecord, ReportSection};

use crate::plausibility::plausibility_checks;

/// Object mass check: failure when `|sum - mass| / mass` exceeds this (reference: 0.5).
pub const MASS_RELATIVE_ERROR_MAX: f64 = 0.5;

/// The intrinsic checks of every part and of the object, and the numbers behind level 4.
#[derive(Debug, Clone, PartialEq)]
pub struct IntrinsicOutcome {
    /// Section `intrinsic` of the report.
    pub section: ReportSection,
    /// `object` metrics: `mass_sum_kg`, `object_mass_kg`, `mass_relative_error`, and the failure
    /// count of each level (`level0_failures` ...).
    pub metrics: BTreeMap<String, f64>,
}

fn check(name: &str, subject: &str, ok: bool, pass: String, fail: String) -> CheckResult {
    CheckResult {
        check: name.to_owned(),
        subject: subject.to_owned(),
        outcome: if ok {
            CheckOutcome::Pass
        } else {
            CheckOutcome::Fail
        },
        message: if ok { pass } else { fail },
    }
}

/// Runs levels 0-4 on a grounded record.
#[must_use]
pub fn verify_intrinsic(record: &AssetRecord) -> IntrinsicOutcome {
    let mut checks: Vec<CheckResult> = record.parts.iter().flat_map(part_checks).collect();
    let (mass_check, mut metrics) = object_mass_check(record);
    checks.push(mass_check);
    checks.extend(plausibility_checks(record));
    for level in 0..=4 {
        let prefix = format!("level{level}_");
        let failures = checks
            .iter()
            .filter(|c| c.check.starts_with(&prefix) && c.outcome == CheckOutcome::Fail)
            .count();
        metrics.insert(format!("level{level}_failures"), failures as f64);
    }
    IntrinsicOutcome {
        section: ReportSection {
            name: "intrinsic".into(),
            checks,
        },
        metrics,
    }
}

/// Levels 0-3 of one part: feasible values, material prior (all five properties), hardness over
/// Young's modulus for engineering materials, friction of interaction surfaces.
#[must_use]
pub fn part_checks(part: &PartRecord) -> Vec<CheckResult> {
    let p = &part.properties;
    let subject = part.id.to_string();
    let (rho, e, h, nu, mu) = (
        p.density_kg_per_m3.value,
        p.youngs_modulus_pa.value,
        p.hardness_pa.value,
        p.poisson_ratio.value,
        p.friction_coefficient.value,
    );
    let mut problems = Vec::new();
    if !(0.0..=3.0).contains(&mu) {
        problems.push(format!("unreasonable friction {mu}"));
    }
    if !(e > 0.0 && e <= 1e12) {
        problems.push(format!("unreasonable Young's modulus {e} Pa"));
    }
    if !(nu > -1.0 && nu < 0.5) {
        problems.push(format!("invalid Poisson ratio {nu}"));
    }
    if !(rho > 0.0 && rho <= 30000.0) {
        problems.push(format!("unreasonable density {rho} kg/m^3"));
    }
    if !(h > 0.0 && h.is_finite()) {
        problems.push(format!("unreasonable hardness {h} Pa"));
    }
    let mut out = vec![check(
        "level0_feasible_values",
        &subject,
        problems.is_empty(),
        "all values feasible".into(),
        problems.join("; "),
    )];
    let category = p.material.value.category;
    match category.prior() {
        Some(prior) => {
            let outside: Vec<String> = [
                ("density", prior.density_kg_per_m3.contains(rho), rho),
                ("young", prior.youngs_modulus_pa.contains(e), e),
                ("hardness", prior.hardness_pa.contains(h), h),
                ("poisson", prior.poisson_ratio.contains(nu), nu),
                ("friction", prior.friction_coefficient.contains(mu), mu),
            ]
            .into_iter()
            .filter(|(_, ok, _)| !ok)
            .map(|(k, _, v)| format!("{k} = {v}"))
            .collect();
            out.push(check(
                "level1_material_prior",
                &subject,
                outside.is_empty(),
                format!("inside the {} prior", category.as_str()),
                format!(
                    "outside the {} prior: {}",
                    category.as_str(),
                    outside.join(", ")
                ),
            ));
        }
        None => out.push(CheckResult {
            check: "level1_material_prior".into(),
            subject: subject.clone(),
            outcome: CheckOutcome::Skipped,
            message: format!("material `{}` has no prior", category.as_str()),
        }),
    }
    if category.hardness_ratio_applies() && e > 0.0 && h > 0.0 {
        let ratio = h / e;
        out.push(check(
            "level2_hardness_modulus_ratio",
            &subject,
            (1e-3..=1e-1).contains(&ratio),
            format!("H/E = {ratio:.2e}"),
            format!("H/E = {ratio:.2e} outside [1e-3, 1e-1]"),
        ));
    }
    if p.affordance_rank.value <= 2 || p.graspable.value {
        out.push(check(
            "level3_interaction_friction",
            &subject,
            mu >= 0.2,
            format!("mu = {mu}"),
            format!(
                "low-friction interaction surface (affordance {}, graspable {}): mu = {mu} < 0.2",
                p.affordance_rank.value, p.graspable.value
            ),
        ));
    }
    out
}

/// Level 4: the object's mass against the sum of the parts' density times volume, the volumes
/// scaled by the ratio of the object's stated dimensions to its mesh extents (both products, so
/// the order of the dimensions does not matter).
fn object_mass_check(record: &AssetRecord) -> (CheckResult, BTreeMap<String, f64>) {
    let bounds = record.parts.iter().fold(Aabb::EMPTY, |b, p| {
        b.union(Aabb {
            min: DVec3::from_array(p.bounds_in_object_m[0]),
            max: DVec3::from_array(p.bounds_in_object_m[1]),
        })
    });
    let extents = bounds.extents();
    let mesh_volume = extents.x * extents.y * extents.z;
    let dims = record.object.dimensions_m.value;
    let stated_volume = dims[0] * dims[1] * dims[2];
    let scale = if mesh_volume > 0.0 && stated_volume > 0.0 {
        stated_volume / mesh_volume
    } else {
        1.0
    };
    let mut problems = Vec::new();
    let mut sum = 0.0;
    for part in &record.parts {
        let v = part.mass.volume_m3;
        if !(v.is_finite() && v > 0.0) {
            problems.push(format!("part {}: missing volume", part.id));
            continue;
        }
        let m = part.properties.density_kg_per_m3.value * v * scale;
        if m <= 0.0 {
            problems.push(format!("part {}: non-positive mass {m} kg", part.id));
        }
        sum += m;
    }
    let mass = record.object.mass_kg.value;
    let relative = (sum - mass).abs() / mass.max(1e-6);
    if relative > MASS_RELATIVE_ERROR_MAX {
        problems.push(format!(
            "mass inconsistency: sum(parts) = {sum:.4} kg vs object = {mass:.4} kg, relative error {relative:.3}"
        ));
    }
    let metrics = BTreeMap::from([
        ("mass_sum_kg".to_owned(), sum),
        ("object_mass_kg".to_owned(), mass),
        ("mass_relative_error".to_owned(), relative),
        ("volume_scale".to_owned(), scale),
    ]);
    let check = check(
        "level4_object_mass",
        "object",
        problems.is_empty(),
        format!("sum(parts) = {sum:.4} kg vs object = {mass:.4} kg, relative error {relative:.3}"),
        problems.join("; "),
    );
    (check, metrics)
}
