//! `report.json`: what was read from the input, estimated by a provider, derived by a rule or
//! defaulted, for every value; the checks that ran; and notes.

use std::collections::BTreeMap;

use serde_json::{Value, json};
use uniphys_types::{AssetRecord, Estimate, Provenance, VerificationReport};

use crate::model::Model;
use crate::{Artifact, ExportResult};

struct Row {
    subject: String,
    field: &'static str,
    value: Value,
    provenance: Provenance,
}

fn row<T: serde::Serialize>(subject: &str, field: &'static str, e: &Estimate<T>) -> Row {
    Row {
        subject: subject.to_owned(),
        field,
        value: json!(e.value),
        provenance: e.provenance.clone(),
    }
}

pub(crate) fn report_artifact(
    record: &AssetRecord,
    report: &VerificationReport,
    notes: &[String],
    contact_excludes: &[Value],
) -> ExportResult<Artifact> {
    let o = &record.object;
    let mut rows = vec![
        row("object", "name", &o.name),
        row("object", "category", &o.category),
        row("object", "dimensions_m", &o.dimensions_m),
        row("object", "mass_kg", &o.mass_kg),
    ];
    for part in &record.parts {
        let s = part.id.to_string();
        let p = &part.properties;
        rows.extend([
            Row {
                subject: s.clone(),
                field: "material",
                value: json!(p.material.value.to_string()),
                provenance: p.material.provenance.clone(),
            },
            row(&s, "density_kg_per_m3", &p.density_kg_per_m3),
            row(&s, "youngs_modulus_pa", &p.youngs_modulus_pa),
            row(&s, "hardness_pa", &p.hardness_pa),
            row(&s, "poisson_ratio", &p.poisson_ratio),
            row(&s, "friction_coefficient", &p.friction_coefficient),
            row(&s, "affordance_rank", &p.affordance_rank),
            row(&s, "graspable", &p.graspable),
            row(&s, "mass_kg", &part.mass.mass_kg),
        ]);
    }
    for joint in &record.joints {
        rows.push(Row {
            subject: format!("joint {}", joint.name),
            field: "joint",
            value: json!({ "kind": joint.kind, "axis": joint.axis_in_object, "pivot_m": joint.pivot_in_object_m, "limits": joint.limits }),
            provenance: joint.provenance.clone(),
        });
    }
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for r in &rows {
        *counts.entry(r.provenance.label()).or_default() += 1;
    }
    let movable = record.joints.iter().filter(|j| j.kind.is_movable()).count();
    let value = json!({
        "schema_version": uniphys_types::SCHEMA_VERSION,
        "asset": record.name,
        "passed": report.passed(),
        "failures": report.failures().map(|c| format!("{} {}: {}", c.subject, c.check, c.message)).collect::<Vec<_>>(),
        "summary": {
            "parts": record.parts.len(),
            "movable_joints": movable,
            "fixed_joints": record.joints.len() - movable,
            "mass_kg": o.mass_kg.value,
            "dimensions_m": o.dimensions_m.value,
            "frame": "Z up, metres, object resting on z = 0 and centred in x and y",
            "source": record.source,
        },
        "provenance_counts": counts,
        "values": rows.iter().map(|r| json!({ "subject": r.subject, "field": r.field, "value": r.value, "provenance": r.provenance })).collect::<Vec<_>>(),
        "sections": report.sections,
        "metrics": report.metrics,
        "contact_excludes": contact_excludes,
        "notes": notes,
    });
    Artifact::json("report.json", &value)
}

/// The pairs of links whose contacts the MJCF excludes on purpose, by link name, with why.
pub(crate) fn contact_excludes(model: &Model<'_>) -> Vec<Value> {
    model
        .exclude_pairs
        .iter()
        .map(|&(a, b, why)| {
            json!({ "links": [model.links[a].name, model.links[b].name], "why": why.label() })
        })
        .collect()
}
