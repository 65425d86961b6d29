//! Checks run on the exported model: what simulators need (checklist 2.6) and the quick
//! intrinsic checks of the reference's levels 0-3. Full verification in simulation is a stage
//! of its own.

use uniphys_geometry::{DMat3, MassProperties, TriMesh, inertia_is_physical};
use uniphys_types::{AssetRecord, CheckOutcome, CheckResult, JointKind, PartRecord, ReportSection};

fn check(
    check: &str,
    subject: impl Into<String>,
    ok: bool,
    pass: impl Into<String>,
    fail: impl Into<String>,
) -> CheckResult {
    CheckResult {
        check: check.to_owned(),
        subject: subject.into(),
        outcome: if ok {
            CheckOutcome::Pass
        } else {
            CheckOutcome::Fail
        },
        message: if ok { pass.into() } else { fail.into() },
    }
}

/// Simulator-facing checks on links, colliders and joints.
pub(crate) fn export_checks(record: &AssetRecord, colliders: &[Vec<TriMesh>]) -> ReportSection {
    let mut checks = Vec::new();
    for (part, hulls) in record.parts.iter().zip(colliders) {
        let subject = part.id.to_string();
        let m = part.mass.mass_kg.value;
        checks.push(check(
            "mass_positive",
            &subject,
            m.is_finite() && m > 0.0,
            format!("{m:.6} kg"),
            format!("mass {m} kg is not positive"),
        ));
        let inertia = DMat3::from_cols_array_2d(&part.mass.inertia_about_com_kg_m2);
        checks.push(check(
            "inertia_physical",
            &subject,
            inertia_is_physical(&inertia),
            "positive definite, triangle inequality holds",
            "inertia is not positive definite or breaks the triangle inequality",
        ));
        let closed = hulls
            .iter()
            .all(|h| MassProperties::from_closed_mesh(h).is_some());
        checks.push(check(
            "convex_colliders",
            &subject,
            !hulls.is_empty() && closed,
            format!("{} closed convex hulls", hulls.len()),
            if hulls.is_empty() {
                "no collision geometry".to_owned()
            } else {
                "a collision hull is not a closed solid".to_owned()
            },
        ));
    }
    for joint in &record.joints {
        let subject = format!("joint {}", joint.name);
        if joint.kind.needs_limits() {
            checks.push(check(
                "limits_present",
                &subject,
                joint.limits.is_some(),
                "limits set",
                "revolute/prismatic joint without limits",
            ));
        }
        if joint.kind.is_movable() {
            checks.push(check(
                "passive_dynamics",
                &subject,
                joint.damping > 0.0,
                format!(
                    "damping {:.4}, friction {:.4}",
                    joint.damping, joint.friction
                ),
                "joint has no damping",
            ));
        }
        if joint.kind == JointKind::Continuous {
            checks.push(CheckResult {
                check: "limits_present".into(),
                subject,
                outcome: CheckOutcome::Skipped,
                message: "continuous joint: no limits by definition".into(),
            });
        }
    }
    ReportSection {
        name: "export".into(),
        checks,
    }
}

/// Quick intrinsic checks per part: feasible values (level 0), material prior (level 1, all five
/// properties), hardness/modulus ratio (level 2), friction of interaction surfaces (level 3).
pub(crate) fn intrinsic_checks(record: &AssetRecord) -> ReportSection {
    let mut checks = Vec::new();
    for part in &record.parts {
        checks.extend(part_intrinsic_checks(part));
    }
    ReportSection {
        name: "intrinsic".into(),
        checks,
    }
}

pub(crate) fn part_intrinsic_checks(part: &PartRecord) -> Vec<CheckResult> {
    let p = &part.properties;
    let subject = part.id.to_string();
    let (rho, e, h, nu, mu) = (
        p.density_kg_per_m3.value,
        p.youngs_modulus_pa.value,
        p.hardness_pa.value,
        p.poisson_ratio.value,
        p.friction_coefficient.value,
    );
    let feasible = (0.0..=3.0).contains(&mu)
        && e > 0.0
        && e <= 1e12
        && nu > -1.0
        && nu < 0.5
        && rho > 0.0
        && rho <= 30000.0;
    let mut out = vec![check(
        "feasible_values",
        &subject,
        feasible,
        "all values feasible",
        format!("rho={rho}, E={e}, nu={nu}, mu={mu}"),
    )];
    let category = p.material.value.category;
    match category.prior() {
        Some(prior) => {
            let outside: Vec<&str> = [
                ("density", prior.density_kg_per_m3.contains(rho)),
                ("young", prior.youngs_modulus_pa.contains(e)),
                ("hardness", prior.hardness_pa.contains(h)),
                ("poisson", prior.poisson_ratio.contains(nu)),
                ("friction", prior.friction_coefficient.contains(mu)),
            ]
            .into_iter()
            .filter(|(_, ok)| !ok)
            .map(|(k, _)| k)
            .collect();
            out.push(check(
                "material_prior",
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
            check: "material_prior".into(),
            subject: subject.clone(),
            outcome: CheckOutcome::Skipped,
            message: "material `other` has no prior".into(),
        }),
    }
    if category.hardness_ratio_applies() && e > 0.0 && h > 0.0 {
        let ratio = h / e;
        out.push(check(
            "hardness_modulus_ratio",
            &subject,
            (1e-3..=1e-1).contains(&ratio),
            format!("H/E = {ratio:.2e}"),
            format!("H/E = {ratio:.2e} outside [1e-3, 1e-1]"),
        ));
    }
    if p.affordance_rank.value <= 2 || p.graspable.value {
        out.push(check(
            "interaction_friction",
            &subject,
            mu >= 0.2,
            format!("mu = {mu}"),
            format!("interaction surface with low friction mu = {mu}"),
        ));
    }
    out
}
