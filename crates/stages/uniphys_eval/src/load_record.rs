//! Our own outputs as evaluation inputs: `record.json` (an [`AssetRecord`]) of a `uniphys run`
//! output directory.

use std::path::{Path, PathBuf};

use uniphys_types::units::{density_g_per_cm3_from_kg_per_m3, gpa_from_pa, hv_from_pa};
use uniphys_types::{AssetRecord, Joint, JointKind, PartId, PartRecord};

use crate::annotated::{
    AnnotatedAsset, AnnotatedJoint, AnnotatedPart, sorted_members, union_bounds,
};
use crate::{EvalError, EvalResult, ObjectValues, PhysicalProperties};

/// File name of the record in a `uniphys run` output directory.
pub const RECORD_FILE: &str = "record.json";

/// The `record.json` behind `path`: the file itself, or `<dir>/record.json` for an output
/// directory; `None` if there is none.
#[must_use]
pub fn record_path(path: &Path) -> Option<PathBuf> {
    if path.is_dir() {
        let inner = path.join(RECORD_FILE);
        inner.is_file().then_some(inner)
    } else {
        (path.is_file()
            && path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json")))
        .then(|| path.to_path_buf())
    }
}

/// Reads the [`AssetRecord`] at `path` (a `record.json` or an output directory holding one).
pub fn read_record(path: &Path) -> EvalResult<AssetRecord> {
    let file = record_path(path).ok_or_else(|| EvalError::UnrecognisedInput {
        path: path.to_path_buf(),
        expected: "a record.json or a `uniphys run` output directory holding one",
    })?;
    let bytes = std::fs::read(&file).map_err(|source| EvalError::Io {
        path: file.clone(),
        source,
    })?;
    serde_json::from_slice(&bytes).map_err(|e| EvalError::Json {
        path: file,
        what: "record.json (AssetRecord)",
        message: e.to_string(),
    })
}

/// An [`AssetRecord`] as one side of an evaluation pair: every part with its properties in the
/// dataset's units, every joint with its coupled group, the object's dimensions and mass, and
/// the union of the parts' bounds.
#[must_use]
pub fn annotated_from_record(record: &AssetRecord, origin: &str) -> AnnotatedAsset {
    let name_of = |id: PartId| {
        record
            .part(id)
            .map_or_else(|| id.to_string(), |p| p.name.clone())
    };
    let bounds = record.parts.iter().fold(None, |acc, p| {
        union_bounds(acc, p.bounds_in_object_m[0], p.bounds_in_object_m[1])
    });
    let object = &record.object;
    AnnotatedAsset {
        origin: origin.to_owned(),
        bounds_in_object: bounds,
        parts: record.parts.iter().map(annotated_part).collect(),
        joints: record
            .joints
            .iter()
            .map(|j| annotated_joint(j, &name_of))
            .collect(),
        object: Some(ObjectValues {
            dimensions: Some(object.dimensions_m.value.to_vec()),
            mass: Some(object.mass_kg.value),
            category: Some(object.category.value.clone()),
        }),
    }
}

fn annotated_part(part: &PartRecord) -> AnnotatedPart {
    let p = &part.properties;
    AnnotatedPart {
        name: part.name.clone(),
        physics: Some(PhysicalProperties {
            material: Some(p.material.value.to_string()),
            density: Some(density_g_per_cm3_from_kg_per_m3(p.density_kg_per_m3.value)),
            friction: Some(p.friction_coefficient.value),
            affordance: Some(f64::from(p.affordance_rank.value)),
            young: Some(gpa_from_pa(p.youngs_modulus_pa.value)),
            hardness: Some(hv_from_pa(p.hardness_pa.value)),
            poisson: Some(p.poisson_ratio.value),
            graspable: Some(p.graspable.value),
        }),
    }
}

/// A joint of the domain model as an [`AnnotatedJoint`] (shared with the mesh-asset loader).
pub(crate) fn annotated_joint(joint: &Joint, name_of: &dyn Fn(PartId) -> String) -> AnnotatedJoint {
    let range = match (joint.kind, joint.limits) {
        (JointKind::Continuous, _) => Some([0.0, std::f64::consts::TAU]),
        (_, Some(l)) if joint.kind.is_movable() => Some([l.lower, l.upper]),
        _ => None,
    };
    let members = if joint.kind.is_movable() {
        sorted_members(
            std::iter::once(joint.child)
                .chain(joint.coupled_parts.iter().copied())
                .map(name_of),
        )
    } else {
        Vec::new()
    };
    AnnotatedJoint {
        child: name_of(joint.child),
        motion_type: joint.kind.movement_type(),
        axis: joint.axis_in_object,
        pivot_in_object: Some(joint.pivot_in_object_m),
        range,
        members,
    }
}
