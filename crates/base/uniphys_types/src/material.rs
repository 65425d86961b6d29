use serde::{Deserialize, Serialize};

use crate::{TypesError, TypesResult};

/// The material categories of the LVLM contract and the UniPhys-40K dataset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialCategory {
    /// Metals and alloys.
    Metal,
    /// Thermoplastics and thermosets.
    Plastic,
    /// Woven or knitted textiles.
    Fabric,
    /// Natural or synthetic leather.
    Leather,
    /// Open or closed cell foams.
    Foam,
    /// Elastomers.
    Rubber,
    /// Glasses.
    Glass,
    /// Natural stone.
    Stone,
    /// Ceramics and porcelain.
    Ceramics,
    /// Wood and wood composites.
    Wood,
    /// Concrete and cement.
    Concrete,
    /// Anything else; has no prior.
    Other,
}

impl MaterialCategory {
    /// Every category, in the order of the reference prompt.
    pub const ALL: [Self; 12] = [
        Self::Metal,
        Self::Plastic,
        Self::Fabric,
        Self::Leather,
        Self::Foam,
        Self::Rubber,
        Self::Glass,
        Self::Stone,
        Self::Ceramics,
        Self::Wood,
        Self::Concrete,
        Self::Other,
    ];

    /// Lower-case name as used in the LVLM contract (`"metal"`, ...).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Metal => "metal",
            Self::Plastic => "plastic",
            Self::Fabric => "fabric",
            Self::Leather => "leather",
            Self::Foam => "foam",
            Self::Rubber => "rubber",
            Self::Glass => "glass",
            Self::Stone => "stone",
            Self::Ceramics => "ceramics",
            Self::Wood => "wood",
            Self::Concrete => "concrete",
            Self::Other => "other",
        }
    }

    /// Parses a category name, case-insensitively (`"Wood"` and `"wood"` both work).
    pub fn parse(name: &str) -> TypesResult<Self> {
        let lower = name.trim().to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|c| c.as_str() == lower)
            .ok_or_else(|| TypesError::UnknownMaterial(name.to_owned()))
    }

    /// The prior ranges of the reference's material table (SI units), or `None` for `other`.
    #[must_use]
    pub fn prior(self) -> Option<MaterialPrior> {
        MaterialPrior::TABLE
            .iter()
            .find(|(c, _)| *c == self)
            .map(|(_, p)| *p)
    }

    /// Whether the hardness/Young's-modulus ratio check applies (engineering materials only).
    #[must_use]
    pub fn hardness_ratio_applies(self) -> bool {
        !matches!(
            self,
            Self::Rubber | Self::Foam | Self::Fabric | Self::Leather | Self::Other
        )
    }
}

/// A material: a category plus a free-text subtype (`wood/oak`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Material {
    /// The category that selects the prior.
    pub category: MaterialCategory,
    /// Free-text refinement, e.g. `oak` or `stainless steel`; may be empty.
    pub subtype: String,
}

impl Material {
    /// Parses `category/subtype` (the subtype may be absent).
    pub fn parse(text: &str) -> TypesResult<Self> {
        let (category, subtype) = text.split_once('/').unwrap_or((text, ""));
        Ok(Self {
            category: MaterialCategory::parse(category)?,
            subtype: subtype.trim().to_owned(),
        })
    }
}

impl std::fmt::Display for Material {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.subtype.is_empty() {
            f.write_str(self.category.as_str())
        } else {
            write!(f, "{}/{}", self.category.as_str(), self.subtype)
        }
    }
}

/// An inclusive range `[low, high]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PriorRange {
    /// Lower bound.
    pub low: f64,
    /// Upper bound.
    pub high: f64,
}

impl PriorRange {
    const fn new(low: f64, high: f64) -> Self {
        Self { low, high }
    }

    /// Whether `value` lies in the range, bounds included.
    #[must_use]
    pub fn contains(&self, value: f64) -> bool {
        value >= self.low && value <= self.high
    }

    /// Geometric mean of the bounds: the central value on a log scale (all priors are positive).
    #[must_use]
    pub fn log_centre(&self) -> f64 {
        (self.low * self.high).sqrt()
    }

    /// Arithmetic mean of the bounds.
    #[must_use]
    pub fn mid(&self) -> f64 {
        0.5 * (self.low + self.high)
    }
}

/// Feasible ranges of the five intrinsic properties for one material category, in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MaterialPrior {
    /// Density, kg/m^3.
    pub density_kg_per_m3: PriorRange,
    /// Young's modulus, Pa.
    pub youngs_modulus_pa: PriorRange,
    /// Poisson's ratio, unitless.
    pub poisson_ratio: PriorRange,
    /// Vickers hardness expressed in Pa.
    pub hardness_pa: PriorRange,
    /// Friction coefficient, unitless.
    pub friction_coefficient: PriorRange,
}

impl MaterialPrior {
    /// The reference's material prior table (section 11.1), SI units. `other` has no entry.
    pub const TABLE: [(MaterialCategory, MaterialPrior); 11] = [
        (
            MaterialCategory::Metal,
            Self::row(
                (2700.0, 8900.0),
                (5e10, 2.5e11),
                (0.25, 0.35),
                (1e9, 1e10),
                (0.2, 0.8),
            ),
        ),
        (
            MaterialCategory::Plastic,
            Self::row(
                (850.0, 1500.0),
                (5e8, 8e9),
                (0.30, 0.45),
                (5e7, 5e8),
                (0.2, 0.6),
            ),
        ),
        (
            MaterialCategory::Fabric,
            Self::row(
                (300.0, 1500.0),
                (1e6, 1e9),
                (0.30, 0.49),
                (1e5, 1e7),
                (0.4, 1.2),
            ),
        ),
        (
            MaterialCategory::Leather,
            Self::row(
                (600.0, 1000.0),
                (5e7, 5e8),
                (0.35, 0.49),
                (1e6, 5e7),
                (0.5, 1.0),
            ),
        ),
        (
            MaterialCategory::Foam,
            Self::row(
                (20.0, 300.0),
                (1e5, 5e8),
                (0.20, 0.45),
                (1e4, 1e6),
                (0.4, 1.0),
            ),
        ),
        (
            MaterialCategory::Rubber,
            Self::row(
                (900.0, 1400.0),
                (1e6, 1e7),
                (0.45, 0.49),
                (5e5, 5e7),
                (0.6, 1.5),
            ),
        ),
        (
            MaterialCategory::Glass,
            Self::row(
                (2200.0, 2600.0),
                (5e10, 9e10),
                (0.20, 0.25),
                (5e9, 1e10),
                (0.3, 0.9),
            ),
        ),
        (
            MaterialCategory::Stone,
            Self::row(
                (2200.0, 3000.0),
                (2e10, 7e10),
                (0.15, 0.30),
                (3e9, 1e10),
                (0.6, 1.2),
            ),
        ),
        (
            MaterialCategory::Ceramics,
            Self::row(
                (2000.0, 6000.0),
                (1e11, 4e11),
                (0.20, 0.30),
                (1e10, 3e10),
                (0.4, 1.0),
            ),
        ),
        (
            MaterialCategory::Wood,
            Self::row(
                (300.0, 900.0),
                (5e8, 2e10),
                (0.25, 0.40),
                (5e7, 5e8),
                (0.4, 0.9),
            ),
        ),
        (
            MaterialCategory::Concrete,
            Self::row(
                (1800.0, 2600.0),
                (2e10, 4e10),
                (0.15, 0.25),
                (1e9, 5e9),
                (0.6, 1.0),
            ),
        ),
    ];

    const fn row(
        density: (f64, f64),
        young: (f64, f64),
        poisson: (f64, f64),
        hardness: (f64, f64),
        friction: (f64, f64),
    ) -> Self {
        Self {
            density_kg_per_m3: PriorRange::new(density.0, density.1),
            youngs_modulus_pa: PriorRange::new(young.0, young.1),
            poisson_ratio: PriorRange::new(poisson.0, poisson.1),
            hardness_pa: PriorRange::new(hardness.0, hardness.1),
            friction_coefficient: PriorRange::new(friction.0, friction.1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn material_parses_category_and_subtype_case_insensitively() {
        let m = Material::parse("Wood/Hardwood").unwrap();
        assert_eq!(m.category, MaterialCategory::Wood);
        assert_eq!(m.subtype, "Hardwood");
        assert_eq!(m.to_string(), "wood/Hardwood");
        assert_eq!(Material::parse("metal").unwrap().subtype, "");
        assert!(matches!(
            Material::parse("unobtainium/x"),
            Err(TypesError::UnknownMaterial(_))
        ));
    }

    #[test]
    fn every_category_but_other_has_a_prior_with_ordered_bounds() {
        for c in MaterialCategory::ALL {
            match c.prior() {
                None => assert_eq!(c, MaterialCategory::Other),
                Some(p) => {
                    for r in [
                        p.density_kg_per_m3,
                        p.youngs_modulus_pa,
                        p.poisson_ratio,
                        p.hardness_pa,
                        p.friction_coefficient,
                    ] {
                        assert!(r.low < r.high, "{c:?}: {r:?}");
                    }
                }
            }
        }
        let wood = MaterialCategory::Wood.prior().unwrap();
        assert!(wood.density_kg_per_m3.contains(900.0) && !wood.density_kg_per_m3.contains(901.0));
    }
}
