use serde::{Deserialize, Serialize};

use crate::{Estimate, Material};

/// Free-text descriptions of a part, as the LVLM contract names them.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Descriptions {
    /// What the part is.
    pub basic: String,
    /// What it is for.
    pub functional: String,
    /// How it moves.
    pub movement: String,
    /// How it is grasped.
    pub grasp: String,
}

/// Intrinsic physical properties of one part (SI units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartProperties {
    /// Material category and subtype.
    pub material: Estimate<Material>,
    /// Density, kg/m^3.
    pub density_kg_per_m3: Estimate<f64>,
    /// Young's modulus, Pa.
    pub youngs_modulus_pa: Estimate<f64>,
    /// Vickers hardness expressed in Pa.
    pub hardness_pa: Estimate<f64>,
    /// Poisson's ratio, unitless.
    pub poisson_ratio: Estimate<f64>,
    /// Coulomb friction coefficient, unitless.
    pub friction_coefficient: Estimate<f64>,
    /// Affordance rank, 1 (most important for human interaction) to 10.
    pub affordance_rank: Estimate<u8>,
    /// Whether a hand would grasp this part.
    pub graspable: Estimate<bool>,
    /// Text descriptions.
    pub descriptions: Descriptions,
}

/// Object-level properties.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectProperties {
    /// Object name, e.g. `cabinet`.
    pub name: Estimate<String>,
    /// Object category, e.g. `Furniture/StorageFurniture`.
    pub category: Estimate<String>,
    /// Axis-aligned extents (x, y, z) of the object in its Z-up frame, metres.
    pub dimensions_m: Estimate<[f64; 3]>,
    /// Total mass, kg.
    pub mass_kg: Estimate<f64>,
}
