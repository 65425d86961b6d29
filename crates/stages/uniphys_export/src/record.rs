//! The annotation record in the UniPhys-40K layout (reference section 15.2):
//! `parts/part_<id>.obj` in the object frame, `annotations/object.json`,
//! `annotations/part_<id>.json` and `meta_data.json`, in the dataset's units
//! (g/cm^3, GPa, HV, cm; ranges in radians for C and metres for B, pivots in the part-mesh frame,
//! which is the object frame).

use serde_json::{Value, json};
use uniphys_types::units::{cm_from_m, density_g_per_cm3_from_kg_per_m3, gpa_from_pa, hv_from_pa};
use uniphys_types::{AssetRecord, JointKind, PartId, PartRecord};

use crate::{Artifact, ExportResult};

/// Dataset `type_name` written into every record's `index`.
pub const RECORD_TYPE_NAME: &str = "uniphys";

pub(crate) fn record_artifacts(
    record: &AssetRecord,
    part_passed: &dyn Fn(PartId) -> bool,
) -> ExportResult<Vec<Artifact>> {
    let part_mass_sum: f64 = record.parts.iter().map(|p| p.mass.mass_kg.value).sum();
    let object_mass = record.object.mass_kg.value;
    let mass_rate = if part_mass_sum > 0.0 && object_mass > 0.0 {
        (object_mass / part_mass_sum).max(part_mass_sum / object_mass)
    } else {
        f64::INFINITY
    };
    let dims_cm: Vec<f64> = record
        .object
        .dimensions_m
        .value
        .iter()
        .map(|&d| round4(cm_from_m(d)))
        .collect();
    let object = json!({
        "object_name": record.object.name.value,
        "category": record.object.category.value,
        "dimension": dims_cm,
        "object_mass": round4(object_mass),
        "mass_rate": if mass_rate.is_finite() { json!(round4(mass_rate)) } else { Value::Null },
    });
    let mut out = vec![
        Artifact::json("annotations/object.json", &object)?,
        Artifact::json(
            "meta_data.json",
            &json!({ "id": record.name, "schema": "uniphys-40k", "part_ids": record.parts.iter().map(|p| p.id.0).collect::<Vec<_>>() }),
        )?,
    ];
    for part in &record.parts {
        out.push(Artifact::json(
            format!("annotations/{}.json", part.id),
            &part_json(record, part, part_passed(part.id)),
        )?);
    }
    Ok(out)
}

fn part_json(record: &AssetRecord, part: &PartRecord, pass_check: bool) -> Value {
    let p = &part.properties;
    let mut motion_types = Vec::new();
    let mut motion_info = serde_json::Map::new();
    if let Some(joint) = record
        .joints
        .iter()
        .find(|j| j.child == part.id && j.kind.is_movable())
    {
        let key = joint.kind.movement_type().to_string();
        let range = match (joint.kind, joint.limits) {
            (JointKind::Continuous, _) | (_, None) => [0.0, std::f64::consts::TAU],
            (_, Some(l)) => [l.lower, l.upper],
        };
        motion_info.insert(
            key.clone(),
            json!({
                "axis": joint.axis_in_object.map(round6),
                "pos": joint.pivot_in_object_m.map(round6),
                "range": range.map(round6),
            }),
        );
        let mut dependency: Vec<u32> = vec![part.id.0];
        dependency.extend(joint.coupled_parts.iter().map(|p| p.0));
        motion_info.insert("dependency".to_owned(), json!(dependency));
        motion_types.push(key);
    }
    json!({
        "index": { "type_name": RECORD_TYPE_NAME, "entity": record.name, "label": part.id.0.to_string() },
        "part_level": {
            "part_name": part.name,
            "basic_description": p.descriptions.basic,
            "functional_description": p.descriptions.functional,
            "movement_description": p.descriptions.movement,
            "grasp_description": p.descriptions.grasp,
            "graspable": p.graspable.value,
            "affordance": p.affordance_rank.value,
        },
        "basic_info": {
            "material": p.material.value.to_string(),
            "density": round4(density_g_per_cm3_from_kg_per_m3(p.density_kg_per_m3.value)),
            "young": round4(gpa_from_pa(p.youngs_modulus_pa.value)),
            "hardness": round4(hv_from_pa(p.hardness_pa.value)),
            "poisson": round4(p.poisson_ratio.value),
            "friction": round4(p.friction_coefficient.value),
            "pass_check": pass_check,
        },
        "kinematic_info": { "motion_types": motion_types, "motion_info": motion_info },
    })
}

fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

fn round6(x: f64) -> f64 {
    let r = (x * 1e6).round() / 1e6;
    if r == 0.0 { 0.0 } else { r }
}
