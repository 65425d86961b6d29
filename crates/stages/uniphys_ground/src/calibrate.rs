//! Walls calibrated by the kind's typical mass. A part modelled as walls along its surface
//! ([`crate::part_mass_model`]) takes its thickness from what its material is usually made
//! of, and that is the least known input of its mass: a real oven's sheet is 0.6 to 1.5 mm, a
//! desk's boards 16 to 40 mm, and a model may draw both faces of a board or only one. The
//! object's kind knows what such objects weigh. Where the walls carry the object's mass, the two
//! are independent estimates of it, each uncertain by a factor of about 2, so the walls (not the
//! parts measured as solids) are thickened or thinned by the square root of the kind's mass over
//! the object's own estimate: an object of walls alone then weighs the geometric mean of the
//! two, and one that is mostly solid barely changes. At most [`MAX_WALL_FACTOR`] either way.

/// Weight of the kind's typical mass against the walls' own estimate, in log space.
pub const TYPICAL_MASS_WEIGHT: f64 = 0.5;
/// The walls are thickened or thinned by at most this factor.
pub const MAX_WALL_FACTOR: f64 = 4.0;

/// The factor to apply to the walls' mass (and inertia): `typical_kg` over the object's own
/// estimate (`walls_kg + solids_kg`), to the power [`TYPICAL_MASS_WEIGHT`], within
/// [`MAX_WALL_FACTOR`] either way. 1 when there are no walls or a mass is not positive.
#[must_use]
pub fn wall_factor(walls_kg: f64, solids_kg: f64, typical_kg: f64) -> f64 {
    let own_kg = walls_kg + solids_kg;
    if !(walls_kg > 0.0 && own_kg.is_finite() && typical_kg > 0.0 && typical_kg.is_finite()) {
        return 1.0;
    }
    (typical_kg / own_kg)
        .powf(TYPICAL_MASS_WEIGHT)
        .clamp(1.0 / MAX_WALL_FACTOR, MAX_WALL_FACTOR)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walls_four_times_too_heavy_end_twice_the_typical_mass() {
        let k = wall_factor(160.0, 0.0, 40.0);
        assert!((160.0 * k - 80.0).abs() < 1e-9, "{k}");
    }

    #[test]
    fn solids_keep_their_mass_and_only_the_walls_move() {
        // Own estimate 4 kg (1 kg solid), typical 16 kg: the walls double, 1 + 6 = 7 kg.
        let k = wall_factor(3.0, 1.0, 16.0);
        assert!((k - 2.0).abs() < 1e-12, "{k}");
        // A solid cabinet with two sheet-metal handles: its handles barely change.
        let k = wall_factor(0.07, 32.0, 35.0);
        assert!((k - (35.0_f64 / 32.07).sqrt()).abs() < 1e-12, "{k}");
    }

    #[test]
    fn the_factor_is_bounded_and_neutral_without_walls() {
        assert!((wall_factor(1.0, 0.0, 1e6) - MAX_WALL_FACTOR).abs() < 1e-12);
        assert!((wall_factor(1.0, 50.0, 0.01) - 1.0 / MAX_WALL_FACTOR).abs() < 1e-12);
        assert_eq!(wall_factor(0.0, 2.0, 40.0), 1.0);
        assert_eq!(wall_factor(2.0, 0.0, f64::NAN), 1.0);
    }
}
