//! The walls of an asset's parts calibrated by its kind's typical mass
//! ([`uniphys_ground::wall_factor`]), applied to the part records and the rigid masses the
//! grounder articulates with.

use uniphys_ground::{RigidMass, wall_factor};
use uniphys_types::{Estimate, PartRecord, Provenance};

/// The rule name of a wall part's mass once calibrated.
const CALIBRATED_WALLS_RULE: &str =
    "density_times_surface_area_times_wall_thickness_calibrated_to_kind_mass";

/// Scales the volume, mass and inertia of the parts modelled as walls by [`wall_factor`]
/// against the kind's `typical_kg` (their method gains `_x<factor>`); returns the factor.
pub(crate) fn calibrate_walls(
    parts: &mut [PartRecord],
    rigid: &mut [RigidMass],
    typical_kg: f64,
) -> f64 {
    let is_wall = |p: &PartRecord| p.mass.volume_method.starts_with("shell_");
    let (mut walls_kg, mut solids_kg) = (0.0, 0.0);
    for p in parts.iter() {
        let kg = p.mass.mass_kg.value;
        if is_wall(p) {
            walls_kg += kg;
        } else {
            solids_kg += kg;
        }
    }
    let factor = wall_factor(walls_kg, solids_kg, typical_kg);
    for (part, mass) in parts.iter_mut().zip(rigid.iter_mut()) {
        if !is_wall(part) {
            continue;
        }
        // The walls are thicker or thinner: their volume scales with their mass, so density
        // times volume stays the part's mass.
        mass.mass_kg *= factor;
        mass.inertia_about_com_kg_m2 *= factor;
        part.mass.volume_m3 *= factor;
        part.mass.volume_method = format!("{}_x{factor:.3}", part.mass.volume_method);
        part.mass.mass_kg = Estimate::new(
            part.mass.mass_kg.value * factor,
            Provenance::rule(CALIBRATED_WALLS_RULE),
        );
        for row in &mut part.mass.inertia_about_com_kg_m2 {
            for value in row.iter_mut() {
                *value *= factor;
            }
        }
    }
    factor
}
