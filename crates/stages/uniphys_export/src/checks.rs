//! Checks run on the exported model: what simulators need (checklist 2.6). Intrinsic and
//! articulation verification are a stage of their own (`uniphys_verify`).

use uniphys_geometry::{DMat3, MassProperties, TriMesh, inertia_is_physical};
use uniphys_types::{AssetRecord, CheckOutcome, CheckResult, JointKind, ReportSection};

/// Name of the report section the export adds.
pub(crate) const EXPORT_SECTION: &str = "export";

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
        name: EXPORT_SECTION.into(),
        checks,
    }
}
