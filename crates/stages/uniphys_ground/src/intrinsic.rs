//! Intrinsic properties from a material: typical values for known subtypes, otherwise the centre
//! of the category's prior range, always inside the prior and with a plausible hardness/modulus
//! ratio.

use uniphys_types::units::pa_from_hv;
use uniphys_types::{
    Descriptions, Estimate, Material, MaterialCategory, MaterialPrior, PartProperties, PriorRange,
    Provenance,
};

use crate::BUILTIN_PROVIDER;
use uniphys_types::words::{first_match, tokens};

/// Typical values of common subtypes: (keyword, density kg/m^3, Young's modulus GPa, hardness HV,
/// Poisson's ratio, friction). Handbook values, nudged into the reference prior where they fall
/// just outside it.
const SUBTYPES: [(&str, f64, f64, f64, f64, f64); 12] = [
    ("steel", 7850.0, 200.0, 150.0, 0.29, 0.5),
    ("iron", 7870.0, 170.0, 130.0, 0.28, 0.5),
    ("alu", 2700.0, 69.0, 110.0, 0.33, 0.45),
    ("brass", 8500.0, 100.0, 120.0, 0.34, 0.4),
    ("copper", 8900.0, 117.0, 110.0, 0.34, 0.45),
    ("oak", 750.0, 11.0, 7.0, 0.3, 0.5),
    ("pine", 500.0, 9.0, 6.0, 0.3, 0.5),
    ("walnut", 650.0, 11.0, 6.5, 0.3, 0.5),
    ("abs", 1050.0, 2.3, 10.0, 0.35, 0.4),
    ("nylon", 1150.0, 2.7, 12.0, 0.39, 0.35),
    ("porcelain", 2400.0, 110.0, 1100.0, 0.22, 0.5),
    ("acrylic", 1180.0, 3.2, 20.0, 0.37, 0.45),
];

struct Values {
    density_kg_per_m3: f64,
    youngs_modulus_pa: f64,
    hardness_pa: f64,
    poisson_ratio: f64,
    friction_coefficient: f64,
}

fn subtype_values(material: &Material) -> Option<(&'static str, Values)> {
    let toks = tokens(&material.subtype);
    SUBTYPES
        .iter()
        .find(|row| first_match(&toks, &[row.0]).is_some())
        .map(|&(k, rho, e_gpa, hv, nu, mu)| {
            (
                k,
                Values {
                    density_kg_per_m3: rho,
                    youngs_modulus_pa: e_gpa * 1e9,
                    hardness_pa: pa_from_hv(hv),
                    poisson_ratio: nu,
                    friction_coefficient: mu,
                },
            )
        })
}

fn prior_centre_values(prior: &MaterialPrior, category: MaterialCategory) -> Values {
    let youngs_modulus_pa = prior.youngs_modulus_pa.log_centre();
    let mut hardness_pa = prior.hardness_pa.log_centre();
    if category.hardness_ratio_applies() {
        // Keep H/E inside [1e-3, 1e-1] (the verification rule) while staying in the prior.
        hardness_pa = hardness_pa.clamp(2e-3 * youngs_modulus_pa, 9e-2 * youngs_modulus_pa);
        hardness_pa = hardness_pa.clamp(prior.hardness_pa.low, prior.hardness_pa.high);
    }
    Values {
        density_kg_per_m3: prior.density_kg_per_m3.mid(),
        youngs_modulus_pa,
        hardness_pa,
        poisson_ratio: prior.poisson_ratio.mid(),
        friction_coefficient: prior.friction_coefficient.mid(),
    }
}

/// Affordance rank (1 = most interacted with) and graspability from the part name.
fn affordance(part_name: &str) -> (u8, bool, Provenance) {
    const GRASP: [&str; 6] = ["handle", "knob", "grip", "button", "lever", "pull"];
    const MOVING: [&str; 6] = ["door", "drawer", "lid", "cover", "flap", "screen"];
    let toks = tokens(part_name);
    if let Some(k) = first_match(&toks, &GRASP) {
        return (
            1,
            true,
            Provenance::provider(BUILTIN_PROVIDER, format!("part name suggests {k:?}")),
        );
    }
    if let Some(k) = first_match(&toks, &MOVING) {
        return (
            2,
            true,
            Provenance::provider(BUILTIN_PROVIDER, format!("part name suggests {k:?}")),
        );
    }
    (
        5,
        false,
        Provenance::default_because("no interaction cue in the part name"),
    )
}

/// The built-in grounder's properties for a part of the given material and name.
pub(crate) fn part_properties(
    material: Material,
    material_provenance: Provenance,
    part_name: &str,
) -> PartProperties {
    let prior = material
        .category
        .prior()
        .or(MaterialCategory::Plastic.prior())
        .expect("plastic has a prior");
    let (values, source) = match subtype_values(&material) {
        Some((k, v)) => (v, format!("typical values of {k}")),
        None => (
            prior_centre_values(&prior, material.category),
            format!("centre of the {} prior", material.category.as_str()),
        ),
    };
    let provenance = Provenance::provider(BUILTIN_PROVIDER, source);
    let est = |value: f64, range: PriorRange| {
        Estimate::with_range(
            value.clamp(range.low, range.high),
            range.low,
            range.high,
            provenance.clone(),
        )
    };
    let (rank, graspable, affordance_provenance) = affordance(part_name);
    PartProperties {
        density_kg_per_m3: est(values.density_kg_per_m3, prior.density_kg_per_m3),
        youngs_modulus_pa: est(values.youngs_modulus_pa, prior.youngs_modulus_pa),
        hardness_pa: est(values.hardness_pa, prior.hardness_pa),
        poisson_ratio: est(values.poisson_ratio, prior.poisson_ratio),
        friction_coefficient: est(values.friction_coefficient, prior.friction_coefficient),
        material: Estimate::new(material, material_provenance),
        affordance_rank: Estimate::new(rank, affordance_provenance.clone()),
        graspable: Estimate::new(graspable, affordance_provenance),
        descriptions: Descriptions {
            basic: part_name.replace('_', " "),
            ..Descriptions::default()
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_category_default_lies_in_its_prior_with_a_plausible_hardness_ratio() {
        for category in MaterialCategory::ALL {
            let p = part_properties(
                Material {
                    category,
                    subtype: String::new(),
                },
                Provenance::rule("test"),
                "part",
            );
            let prior = category
                .prior()
                .or(MaterialCategory::Plastic.prior())
                .unwrap();
            assert!(
                prior.density_kg_per_m3.contains(p.density_kg_per_m3.value),
                "{category:?}"
            );
            assert!(
                prior.youngs_modulus_pa.contains(p.youngs_modulus_pa.value),
                "{category:?}"
            );
            assert!(
                prior.hardness_pa.contains(p.hardness_pa.value),
                "{category:?}"
            );
            assert!(
                prior.poisson_ratio.contains(p.poisson_ratio.value),
                "{category:?}"
            );
            assert!(
                prior
                    .friction_coefficient
                    .contains(p.friction_coefficient.value),
                "{category:?}"
            );
            if category.hardness_ratio_applies() {
                let ratio = p.hardness_pa.value / p.youngs_modulus_pa.value;
                assert!(
                    (1e-3..=1e-1).contains(&ratio),
                    "{category:?}: H/E = {ratio}"
                );
            }
        }
    }

    #[test]
    fn known_subtypes_use_handbook_values_inside_the_prior() {
        for (k, ..) in SUBTYPES {
            let category = if ["oak", "pine", "walnut"].contains(&k) {
                MaterialCategory::Wood
            } else if ["abs", "nylon", "acrylic"].contains(&k) {
                MaterialCategory::Plastic
            } else if k == "porcelain" {
                MaterialCategory::Ceramics
            } else {
                MaterialCategory::Metal
            };
            let p = part_properties(
                Material {
                    category,
                    subtype: k.to_owned(),
                },
                Provenance::rule("test"),
                "x",
            );
            let prior = category.prior().unwrap();
            assert!(prior.hardness_pa.contains(p.hardness_pa.value), "{k}");
            let ratio = p.hardness_pa.value / p.youngs_modulus_pa.value;
            assert!((1e-3..=1e-1).contains(&ratio), "{k}: {ratio}");
        }
        let steel = part_properties(
            Material::parse("metal/steel").unwrap(),
            Provenance::rule("t"),
            "door_handle",
        );
        assert!((steel.density_kg_per_m3.value - 7850.0).abs() < 1e-9);
        assert_eq!(steel.affordance_rank.value, 1);
        assert!(steel.graspable.value);
    }
}
