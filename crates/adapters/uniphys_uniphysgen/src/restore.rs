//! Model answers back to the object frame and SI units (reference 14.5
//! `restore_motion_to_annotation_units`), refusing answers that make no sense.

use std::f64::consts::TAU;

use uniphys_geometry::DVec3;
use uniphys_types::units::{
    M_PER_CM, density_kg_per_m3_from_g_per_cm3, m_from_cm, pa_from_gpa, pa_from_hv, rad_from_deg,
};
use uniphys_types::{
    Descriptions, Estimate, JointKind, JointLimits, Material, PartId, PartProperties, Provenance,
};

use crate::contract::{AxisAnswer, ObjectAnswer, PartAnswer, PhysicsAnswer};
use crate::{CoordinateFrame, UniPhysGenError, UniPhysGenResult};

/// Provider name in the provenance of every restored value.
pub const PROVIDER: &str = "uniphysgen";

/// A predicted joint of a part, as [`uniphys_types::Joint`] holds it (the parent is not
/// predicted by the kinematics task; the caller picks it).
#[derive(Debug, Clone, PartialEq)]
pub struct RestoredMotion {
    /// `Prismatic` (motion type B) or `Revolute` (C).
    pub kind: JointKind,
    /// Unit axis, object frame (the model frame has the same axes).
    pub axis_in_object: [f64; 3],
    /// Pivot, object frame, metres.
    pub pivot_in_object_m: [f64; 3],
    /// Limits, radians (revolute) or metres (prismatic), `lower <= upper`; `None` if the model
    /// gave no range.
    pub limits: Option<JointLimits>,
    /// `provider: uniphysgen/<model>`.
    pub provenance: Provenance,
}

/// The object-level answer in SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct RestoredObject {
    /// Object name.
    pub name: Estimate<String>,
    /// Category.
    pub category: Estimate<String>,
    /// Dimensions `[L, W, H]`, metres, if the model gave them.
    pub dimensions_m: Option<Estimate<[f64; 3]>>,
    /// Volume, m^3, if the model gave it.
    pub volume_m3: Option<Estimate<f64>>,
    /// Mass, kg.
    pub mass_kg: Estimate<f64>,
}

/// Unit vector of spherical angles in degrees: `[sin t cos p, sin t sin p, cos t]` with `t` the
/// polar angle from +z and `p` the azimuth from +x towards +y.
#[must_use]
pub fn axis_from_spherical_deg(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (theta, phi) = (rad_from_deg(theta_deg), rad_from_deg(phi_deg));
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

fn invalid(part: &str, reason: impl Into<String>) -> UniPhysGenError {
    UniPhysGenError::InvalidAnswer {
        part: part.to_owned(),
        reason: reason.into(),
    }
}

fn finite(part: &str, field: &str, values: &[f64]) -> UniPhysGenResult<()> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(invalid(part, format!("{field} {values:?} is not finite")))
    }
}

/// The unit axis of an answer (spherical degrees or a vector).
///
/// # Errors
/// [`UniPhysGenError::InvalidAnswer`] for non-finite numbers or a zero vector.
pub fn restore_axis(part: &str, axis: &AxisAnswer) -> UniPhysGenResult<DVec3> {
    let vector = match *axis {
        AxisAnswer::Spherical { theta, phi } => {
            finite(part, "axis angles", &[theta, phi])?;
            axis_from_spherical_deg(theta, phi)
        }
        AxisAnswer::Vector(v) => {
            finite(part, "axis", &v)?;
            DVec3::from_array(v)
        }
    };
    vector
        .try_normalize()
        .ok_or_else(|| invalid(part, "the axis is the zero vector"))
}

/// A kinematics answer in the object frame: `None` if the part does not move (motion type
/// null). Axis from spherical degrees; pivot `(p + min_bound) * scale + center`; prismatic range
/// times the scale (metres), revolute range times 2*pi (radians), sorted. A prismatic answer
/// without a pivot gets the part centre (the model is trained on the centroid there).
///
/// # Errors
/// [`UniPhysGenError::InvalidAnswer`] if the motion type is not B, C or null, a range comes
/// with a null motion type, the axis (or a revolute pivot) is missing or zero, or a number is
/// not finite.
pub fn restore_motion(
    answer: &PartAnswer,
    frame: &CoordinateFrame,
    part_center_in_object_m: DVec3,
    model: &str,
) -> UniPhysGenResult<Option<RestoredMotion>> {
    let part = answer.id.as_str();
    let kind = match answer.motion_type.as_deref() {
        None => {
            if answer.range.is_some() {
                return Err(invalid(
                    part,
                    "a range is given with a null motion_type (a part that does not move has no range)",
                ));
            }
            return Ok(None);
        }
        Some("B") => JointKind::Prismatic,
        Some("C") => JointKind::Revolute,
        Some(other) => {
            return Err(invalid(
                part,
                format!("motion_type {other:?} is not \"B\" (prismatic), \"C\" (revolute) or null"),
            ));
        }
    };
    let axis = answer
        .axis
        .as_ref()
        .ok_or_else(|| invalid(part, "a moving part has no axis"))?;
    let axis = restore_axis(part, axis)?;
    let pivot_in_object_m = match (answer.pivot, kind) {
        (Some(pivot), _) => {
            finite(part, "pivot", &pivot)?;
            frame.point_model_to_source(DVec3::from_array(pivot))
        }
        (None, JointKind::Prismatic) => part_center_in_object_m,
        (None, _) => return Err(invalid(part, "a revolute part has no pivot")),
    };
    let limits = match answer.range {
        Some(range) => {
            finite(part, "range", &range)?;
            let to_si = |r: f64| match kind {
                JointKind::Prismatic => frame.distance_model_to_source(r),
                _ => r * TAU,
            };
            let (a, b) = (to_si(range[0]), to_si(range[1]));
            Some(JointLimits {
                lower: a.min(b),
                upper: a.max(b),
            })
        }
        None => None,
    };
    Ok(Some(RestoredMotion {
        kind,
        axis_in_object: axis.to_array(),
        pivot_in_object_m: pivot_in_object_m.to_array(),
        limits,
        provenance: Provenance::provider(PROVIDER, model),
    }))
}

/// The structure answer's members as part ids, each checked against the asset's part ids
/// (decimal indices).
///
/// # Errors
/// [`UniPhysGenError::InvalidAnswer`] if the answer has no members or names an unknown part.
pub fn restore_members(answer: &PartAnswer, part_ids: &[String]) -> UniPhysGenResult<Vec<PartId>> {
    let part = answer.id.as_str();
    let members = answer
        .members
        .as_ref()
        .ok_or_else(|| invalid(part, "the structure answer has no members"))?;
    let mut ids = Vec::with_capacity(members.len());
    for member in members {
        let known = part_ids.iter().any(|id| id == member);
        let index = member
            .parse::<u32>()
            .ok()
            .filter(|_| known)
            .ok_or_else(|| {
                invalid(
                    part,
                    format!("member {member:?} is not a part of this asset (parts: {part_ids:?})"),
                )
            })?;
        if !ids.contains(&PartId(index)) {
            ids.push(PartId(index));
        }
    }
    Ok(ids)
}

/// A physics answer in SI units (g/cm^3 to kg/m^3, GPa to Pa, HV to Pa) as part properties
/// from `uniphysgen/<model>`. A missing affordance or graspable flag becomes a default (rank
/// 5, not graspable) that says so; descriptions are empty (the checkpoint does not give them).
///
/// # Errors
/// [`UniPhysGenError::InvalidAnswer`] for an unknown material category, non-finite or
/// non-positive density, modulus or hardness, a Poisson ratio outside (-1, 0.5], a negative
/// friction or an affordance outside 1..=10.
pub fn restore_physics(
    part: &str,
    answer: &PhysicsAnswer,
    model: &str,
) -> UniPhysGenResult<PartProperties> {
    let values = [
        answer.density,
        answer.young,
        answer.hardness,
        answer.poisson,
        answer.friction,
    ];
    finite(part, "physical properties", &values)?;
    for (name, value) in [
        ("density", answer.density),
        ("young", answer.young),
        ("hardness", answer.hardness),
    ] {
        if value <= 0.0 {
            return Err(invalid(part, format!("{name} {value} must be positive")));
        }
    }
    if !(answer.poisson > -1.0 && answer.poisson <= 0.5) {
        return Err(invalid(
            part,
            format!("poisson {} must be in (-1, 0.5]", answer.poisson),
        ));
    }
    if answer.friction < 0.0 {
        return Err(invalid(
            part,
            format!("friction {} must not be negative", answer.friction),
        ));
    }
    let material =
        Material::parse(&answer.material).map_err(|e| invalid(part, format!("material: {e}")))?;
    let from_model = || Provenance::provider(PROVIDER, model);
    let missing = |what: &str| {
        Provenance::default_because(format!("the UniPhysGen physics answer has no {what}"))
    };
    let affordance_rank = match answer.affordance {
        Some(rank @ 1..=10) => Estimate::new(rank, from_model()),
        Some(rank) => {
            return Err(invalid(
                part,
                format!("affordance {rank} is outside 1..=10"),
            ));
        }
        None => Estimate::new(5, missing("affordance")),
    };
    let graspable = match answer.graspable {
        Some(flag) => Estimate::new(flag, from_model()),
        None => Estimate::new(false, missing("graspable flag")),
    };
    Ok(PartProperties {
        material: Estimate::new(material, from_model()),
        density_kg_per_m3: Estimate::new(
            density_kg_per_m3_from_g_per_cm3(answer.density),
            from_model(),
        ),
        youngs_modulus_pa: Estimate::new(pa_from_gpa(answer.young), from_model()),
        hardness_pa: Estimate::new(pa_from_hv(answer.hardness), from_model()),
        poisson_ratio: Estimate::new(answer.poisson, from_model()),
        friction_coefficient: Estimate::new(answer.friction, from_model()),
        affordance_rank,
        graspable,
        descriptions: Descriptions::default(),
    })
}

/// The object-level answer in SI units (cm to m, cm^3 to m^3).
///
/// # Errors
/// [`UniPhysGenError::InvalidAnswer`] for non-finite or non-positive dimensions, volume or mass.
pub fn restore_object(answer: &ObjectAnswer, model: &str) -> UniPhysGenResult<RestoredObject> {
    let part = "object";
    let positive = |field: &str, values: &[f64]| -> UniPhysGenResult<()> {
        finite(part, field, values)?;
        if values.iter().all(|&v| v > 0.0) {
            Ok(())
        } else {
            Err(invalid(
                part,
                format!("{field} {values:?} must be positive"),
            ))
        }
    };
    positive("mass", &[answer.mass])?;
    let from_model = || Provenance::provider(PROVIDER, model);
    let dimensions_m = match answer.dimension {
        Some(cm) => {
            positive("dimension", &cm)?;
            Some(Estimate::new(cm.map(m_from_cm), from_model()))
        }
        None => None,
    };
    let volume_m3 = match answer.volume {
        Some(cm3) => {
            positive("volume", &[cm3])?;
            Some(Estimate::new(cm3 * M_PER_CM.powi(3), from_model()))
        }
        None => None,
    };
    Ok(RestoredObject {
        name: Estimate::new(answer.object_name.clone(), from_model()),
        category: Estimate::new(answer.category.clone(), from_model()),
        dimensions_m,
        volume_m3,
        mass_kg: Estimate::new(answer.mass, from_model()),
    })
}
