//! Validated answers → domain types in SI, every value naming the model and the prompt version
//! (`Provenance::provider("lvlm:<model>", PROMPT_VERSION)`).
//!
//! Values are taken as the model gave them: one outside its material's prior stays as it is and
//! the verifier's material-prior level flags it (nothing is clamped here).

use uniphys_types::units::{pa_from_gpa, pa_from_hv};
use uniphys_types::{
    Descriptions, Estimate, Material, MaterialCategory, ObjectProperties, PartProperties,
    Provenance,
};

use crate::prompt::PROMPT_VERSION;
use crate::quantities::{density_kg_per_m3, dimensions_m, mass_kg};
use crate::schema::{PartAnswer, PropertiesAnswer};

/// Provider name of a model in provenance: `lvlm:<model>`.
#[must_use]
pub fn provider_name(model: &str) -> String {
    format!("lvlm:{model}")
}

/// The provenance of every value the model gave.
#[must_use]
pub fn lvlm_provenance(model: &str) -> Provenance {
    Provenance::provider(provider_name(model), PROMPT_VERSION)
}

/// Properties of one validated part answer.
#[must_use]
pub fn part_properties(part: &PartAnswer, model: &str) -> PartProperties {
    let p = lvlm_provenance(model);
    // Validation guarantees the material and density parse; the fallbacks are never used.
    let material = Material::parse(&part.material).unwrap_or(Material {
        category: MaterialCategory::Other,
        subtype: part.material.clone(),
    });
    PartProperties {
        material: Estimate::new(material, p.clone()),
        density_kg_per_m3: Estimate::new(
            density_kg_per_m3(&part.density).unwrap_or(f64::NAN),
            p.clone(),
        ),
        youngs_modulus_pa: Estimate::new(pa_from_gpa(part.youngs_modulus_gpa), p.clone()),
        hardness_pa: Estimate::new(pa_from_hv(part.hardness_hv), p.clone()),
        poisson_ratio: Estimate::new(part.poisson_ratio, p.clone()),
        friction_coefficient: Estimate::new(part.friction_coefficient, p.clone()),
        affordance_rank: Estimate::new(part.affordance_rank, p.clone()),
        graspable: Estimate::new(part.graspable, p),
        descriptions: Descriptions {
            basic: part.descriptions.basic.clone(),
            functional: part.descriptions.functional.clone(),
            movement: part.descriptions.movement.clone(),
            grasp: part.descriptions.grasp.clone(),
        },
    }
}

/// Object properties of a validated answer. The model's `L*W*H` are unordered, so they are
/// assigned to the object's x, y, z by rank: the longest to the axis along which the mesh is
/// longest, and so on (`object_extents_m` are the mesh's extents).
#[must_use]
pub fn object_properties(
    answer: &PropertiesAnswer,
    object_extents_m: [f64; 3],
    model: &str,
) -> ObjectProperties {
    let p = lvlm_provenance(model);
    let mut given = dimensions_m(&answer.dimensions).unwrap_or([f64::NAN; 3]);
    given.sort_by(|a, b| b.total_cmp(a));
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| {
        object_extents_m[b]
            .total_cmp(&object_extents_m[a])
            .then(a.cmp(&b))
    });
    let mut dims = [0.0; 3];
    for (rank, &axis) in axes.iter().enumerate() {
        dims[axis] = given[rank];
    }
    ObjectProperties {
        name: Estimate::new(answer.object_name.clone(), p.clone()),
        category: Estimate::new(answer.category.clone(), p.clone()),
        dimensions_m: Estimate::new(dims, p.clone()),
        mass_kg: Estimate::new(mass_kg(&answer.mass).unwrap_or(f64::NAN), p),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schema::DescriptionsAnswer;

    fn part() -> PartAnswer {
        PartAnswer {
            label: 1,
            name: "lid".into(),
            material: "Wood/pine".into(),
            density: "0.5 g/cm^3".into(),
            youngs_modulus_gpa: 9.0,
            hardness_hv: 4.0,
            poisson_ratio: 0.3,
            friction_coefficient: 0.5,
            affordance_rank: 2,
            graspable: true,
            neighbours: Vec::new(),
            descriptions: DescriptionsAnswer::default(),
        }
    }

    #[test]
    fn part_values_are_converted_to_si_and_name_the_model() {
        let props = part_properties(&part(), "m1");
        assert_eq!(props.material.value.category, MaterialCategory::Wood);
        assert!((props.density_kg_per_m3.value - 500.0).abs() < 1e-9);
        assert!((props.youngs_modulus_pa.value - 9e9).abs() < 1.0);
        assert!((props.hardness_pa.value - 4.0 * 9.807e6).abs() < 1e-3);
        assert_eq!(
            props.graspable.provenance,
            Provenance::provider("lvlm:m1", PROMPT_VERSION)
        );
    }

    #[test]
    fn values_outside_the_material_prior_are_kept_for_the_verifier() {
        let mut heavy = part();
        heavy.density = "7.8 g/cm^3".into();
        heavy.friction_coefficient = 1.9;
        let props = part_properties(&heavy, "m1");
        let prior = MaterialCategory::Wood.prior().map(|p| p.density_kg_per_m3);
        assert!(prior.is_some_and(|r| !r.contains(props.density_kg_per_m3.value)));
        assert!((props.density_kg_per_m3.value - 7800.0).abs() < 1e-9);
        assert!((props.friction_coefficient.value - 1.9).abs() < 1e-12);
    }

    #[test]
    fn unordered_dimensions_follow_the_mesh_extents_by_rank() {
        let answer = PropertiesAnswer {
            object_name: "box".into(),
            category: "c".into(),
            dimensions: "15*30*20 cm".into(),
            mass: "2 kg".into(),
            parts: vec![part()],
        };
        let object = object_properties(&answer, [0.31, 0.19, 0.16], "m1");
        let d = object.dimensions_m.value;
        assert!(
            (d[0] - 0.30).abs() < 1e-12
                && (d[1] - 0.20).abs() < 1e-12
                && (d[2] - 0.15).abs() < 1e-12
        );
        assert!((object.mass_kg.value - 2.0).abs() < 1e-12);
    }
}
