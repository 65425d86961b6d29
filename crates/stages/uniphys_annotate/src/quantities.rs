//! Parsing of the quantities the model writes with units: `"0.7 g/cm^3"`, `"12.5 kg"`,
//! `"60*40*90 cm"`, `"0-30 cm"`, `"0-110 degrees"`. Each parser accepts a few spellings of its
//! unit and returns SI values; anything else is `None` (the validator turns it into a violation
//! that says which unit was expected).

use uniphys_types::units::{density_kg_per_m3_from_g_per_cm3, m_from_cm, rad_from_deg};

/// A motion range in SI: metres for a slide, radians for a rotation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MotionRange {
    /// Translation range, metres.
    Length {
        /// Lower end, m.
        lower_m: f64,
        /// Upper end, m.
        upper_m: f64,
    },
    /// Rotation range, radians.
    Angle {
        /// Lower end, rad.
        lower_rad: f64,
        /// Upper end, rad.
        upper_rad: f64,
    },
}

/// Splits a leading decimal number (optional sign, digits, optional fraction and exponent) off
/// `text`; blanks before it are skipped.
fn take_number(text: &str) -> Option<(f64, &str)> {
    let text = text.trim_start();
    let bytes = text.as_bytes();
    let mut end = 0;
    if matches!(bytes.first(), Some(b'+' | b'-')) {
        end += 1;
    }
    let digits_start = end;
    while end < bytes.len() && (bytes[end].is_ascii_digit() || bytes[end] == b'.') {
        end += 1;
    }
    if end == digits_start {
        return None;
    }
    if end < bytes.len() && matches!(bytes[end], b'e' | b'E') {
        let mut exp = end + 1;
        if exp < bytes.len() && matches!(bytes[exp], b'+' | b'-') {
            exp += 1;
        }
        let exp_digits = exp;
        while exp < bytes.len() && bytes[exp].is_ascii_digit() {
            exp += 1;
        }
        if exp > exp_digits {
            end = exp;
        }
    }
    let value: f64 = text[..end].parse().ok()?;
    value.is_finite().then_some((value, &text[end..]))
}

fn unit_is(rest: &str, spellings: &[&str]) -> bool {
    let unit = rest.trim().to_ascii_lowercase().replace(' ', "");
    spellings.contains(&unit.as_str())
}

/// `"0.7 g/cm^3"` (also `g/cm3`, `g/cm³`, `g cm^-3`) → kg/m^3.
#[must_use]
pub fn density_kg_per_m3(text: &str) -> Option<f64> {
    let (value, rest) = take_number(text)?;
    unit_is(rest, &["g/cm^3", "g/cm3", "g/cm³", "gcm^-3", "g/cc"])
        .then(|| density_kg_per_m3_from_g_per_cm3(value))
}

/// `"12.5 kg"` (also `kgs`, `kilograms`) → kg.
#[must_use]
pub fn mass_kg(text: &str) -> Option<f64> {
    let (value, rest) = take_number(text)?;
    unit_is(rest, &["kg", "kgs", "kilogram", "kilograms"]).then_some(value)
}

/// `"60*40*90 cm"` (separators `*`, `x`, `×`) → three lengths in metres, in the order written.
#[must_use]
pub fn dimensions_m(text: &str) -> Option<[f64; 3]> {
    let mut rest = text;
    let mut out = [0.0; 3];
    for (i, slot) in out.iter_mut().enumerate() {
        let (value, tail) = take_number(rest)?;
        *slot = m_from_cm(value);
        rest = tail.trim_start();
        if i < 2 {
            rest = rest
                .strip_prefix('*')
                .or_else(|| rest.strip_prefix('x'))
                .or_else(|| rest.strip_prefix('X'))
                .or_else(|| rest.strip_prefix('×'))?;
        }
    }
    unit_is(rest, &["cm", "centimetres", "centimeters"]).then_some(out)
}

/// `"0-30 cm"`, `"0-110 degrees"`, `"-90 to 0 deg"`, `"0~0.3 m"` → a [`MotionRange`] in SI.
/// Lengths in mm, cm or m; angles in degrees (`degrees`, `degree`, `deg`, `°`) or radians
/// (`rad`, `radians`).
#[must_use]
pub fn motion_range(text: &str) -> Option<MotionRange> {
    let (lower, rest) = take_number(text)?;
    let rest = rest.trim_start();
    let rest = rest
        .strip_prefix("to")
        .or_else(|| rest.strip_prefix('-'))
        .or_else(|| rest.strip_prefix('~'))
        .or_else(|| rest.strip_prefix('–'))?;
    let (upper, unit) = take_number(rest)?;
    let unit = unit.trim().to_ascii_lowercase();
    let length = |factor: f64| MotionRange::Length {
        lower_m: lower * factor,
        upper_m: upper * factor,
    };
    match unit.as_str() {
        "cm" => Some(length(m_from_cm(1.0))),
        "mm" => Some(length(1e-3)),
        "m" => Some(length(1.0)),
        "degrees" | "degree" | "deg" | "°" | "degs" => Some(MotionRange::Angle {
            lower_rad: rad_from_deg(lower),
            upper_rad: rad_from_deg(upper),
        }),
        "rad" | "radians" | "radian" => Some(MotionRange::Angle {
            lower_rad: lower,
            upper_rad: upper,
        }),
        _ => None,
    }
}

impl MotionRange {
    /// `(lower, upper)` in SI (m or rad).
    #[must_use]
    pub fn bounds(self) -> (f64, f64) {
        match self {
            Self::Length { lower_m, upper_m } => (lower_m, upper_m),
            Self::Angle {
                lower_rad,
                upper_rad,
            } => (lower_rad, upper_rad),
        }
    }

    /// Whether the range is a rotation.
    #[must_use]
    pub fn is_angle(self) -> bool {
        matches!(self, Self::Angle { .. })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densities_masses_and_dimensions_parse_to_si() {
        assert!((density_kg_per_m3("7.8 g/cm^3").unwrap_or(0.0) - 7800.0).abs() < 1e-9);
        assert!((density_kg_per_m3("0.5g/cm3").unwrap_or(0.0) - 500.0).abs() < 1e-9);
        assert_eq!(density_kg_per_m3("7.8 kg"), None);
        assert_eq!(density_kg_per_m3("heavy"), None);
        assert_eq!(mass_kg("0.25 kg"), Some(0.25));
        assert_eq!(mass_kg("250 g"), None);
        let d = dimensions_m("20*3*2 cm").unwrap_or([0.0; 3]);
        assert!((d[0] - 0.2).abs() < 1e-12 && (d[1] - 0.03).abs() < 1e-12);
        assert!(dimensions_m("20 x 3 x 2 cm").is_some());
        assert_eq!(dimensions_m("20*3 cm"), None);
        assert_eq!(dimensions_m("20*3*2 m"), None);
    }

    #[test]
    fn ranges_parse_with_signs_and_units() {
        let Some(MotionRange::Length { lower_m, upper_m }) = motion_range("0-30 cm") else {
            panic!("length range");
        };
        assert!(lower_m.abs() < 1e-12 && (upper_m - 0.3).abs() < 1e-12);
        let Some(MotionRange::Angle {
            lower_rad,
            upper_rad,
        }) = motion_range("-90-0 degrees")
        else {
            panic!("angle range");
        };
        assert!((lower_rad + std::f64::consts::FRAC_PI_2).abs() < 1e-12 && upper_rad == 0.0);
        assert!(motion_range("-45 to 45 deg").is_some_and(MotionRange::is_angle));
        assert_eq!(motion_range("0-30"), None);
        assert_eq!(motion_range("thirty cm"), None);
        assert_eq!(
            motion_range("1e-2-2e-1 m").map(MotionRange::bounds),
            Some((0.01, 0.2))
        );
    }
}
