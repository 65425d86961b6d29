//! Conversions between SI (used everywhere inside the code) and the units of the LVLM contract and
//! the UniPhys-40K dataset records. Apply them only where values enter or leave the system.
//!
//! | quantity | inside (SI) | LVLM / dataset | factor |
//! |---|---|---|---|
//! | density | kg/m^3 | g/cm^3 | 1 g/cm^3 = 1000 kg/m^3 |
//! | Young's modulus | Pa | GPa | 1 GPa = 1e9 Pa |
//! | hardness | Pa | HV (Vickers) | 1 HV = 9.807e6 Pa (the reference's factor) |
//! | length | m | cm | 1 cm = 0.01 m |
//! | angle | rad | degrees | pi/180 |

/// Kilograms per cubic metre in one gram per cubic centimetre.
pub const KG_PER_M3_PER_G_PER_CM3: f64 = 1000.0;
/// Pascals in one gigapascal.
pub const PA_PER_GPA: f64 = 1e9;
/// Pascals in one Vickers hardness unit (kgf/mm^2 taken with g = 9.807 m/s^2, as the reference does).
pub const PA_PER_HV: f64 = 9.807e6;
/// Metres in one centimetre.
pub const M_PER_CM: f64 = 0.01;

/// Converts a density from g/cm^3 to kg/m^3.
#[must_use]
pub fn density_kg_per_m3_from_g_per_cm3(g_per_cm3: f64) -> f64 {
    g_per_cm3 * KG_PER_M3_PER_G_PER_CM3
}

/// Converts a density from kg/m^3 to g/cm^3.
#[must_use]
pub fn density_g_per_cm3_from_kg_per_m3(kg_per_m3: f64) -> f64 {
    kg_per_m3 / KG_PER_M3_PER_G_PER_CM3
}

/// Converts a modulus from GPa to Pa.
#[must_use]
pub fn pa_from_gpa(gpa: f64) -> f64 {
    gpa * PA_PER_GPA
}

/// Converts a modulus from Pa to GPa.
#[must_use]
pub fn gpa_from_pa(pa: f64) -> f64 {
    pa / PA_PER_GPA
}

/// Converts a Vickers hardness (HV) to Pa.
#[must_use]
pub fn pa_from_hv(hv: f64) -> f64 {
    hv * PA_PER_HV
}

/// Converts a hardness in Pa to Vickers (HV).
#[must_use]
pub fn hv_from_pa(pa: f64) -> f64 {
    pa / PA_PER_HV
}

/// Converts centimetres to metres.
#[must_use]
pub fn m_from_cm(cm: f64) -> f64 {
    cm * M_PER_CM
}

/// Converts metres to centimetres.
#[must_use]
pub fn cm_from_m(m: f64) -> f64 {
    m / M_PER_CM
}

/// Converts degrees to radians.
#[must_use]
pub fn rad_from_deg(deg: f64) -> f64 {
    deg.to_radians()
}

/// Converts radians to degrees.
#[must_use]
pub fn deg_from_rad(rad: f64) -> f64 {
    rad.to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip_and_match_reference_factors() {
        assert!((density_kg_per_m3_from_g_per_cm3(0.7) - 700.0).abs() < 1e-9);
        assert!((pa_from_hv(4.0) - 39.228e6).abs() < 1e-3);
        assert!((gpa_from_pa(pa_from_gpa(10.0)) - 10.0).abs() < 1e-12);
        assert!((hv_from_pa(pa_from_hv(123.0)) - 123.0).abs() < 1e-9);
        assert!((m_from_cm(20.0) - 0.2).abs() < 1e-12);
        assert!((cm_from_m(0.25) - 25.0).abs() < 1e-12);
        assert!((deg_from_rad(rad_from_deg(90.0)) - 90.0).abs() < 1e-12);
        assert!((density_g_per_cm3_from_kg_per_m3(7800.0) - 7.8).abs() < 1e-12);
    }
}
