//! `--unit auto`: an input whose coordinates are not a length (a PartNet-Mobility folder,
//! normalised so that its largest side is about 1 to 2) is scaled to the typical size of its
//! kind; an input whose unit is fixed or conventional (metres) keeps it unless that makes the
//! object implausibly large or small for its kind, when the common unit that fits is used.

use uniphys_ground::ObjectKind;
use uniphys_mesh_io::InputUnits;

/// An input read as metres is implausible for its kind when its largest side is off the kind's
/// typical one by more than this factor either way.
const IMPLAUSIBLE_FACTOR: f64 = 5.0;

/// Units an unlabelled file is commonly drawn in, metres per unit.
const COMMON_UNITS: [(&str, f64); 4] = [("m", 1.0), ("cm", 0.01), ("mm", 0.001), ("in", 0.0254)];

/// The factor that brings an input, read as metres with largest side `largest_side_m`, to a
/// real size, and a note saying why (`None` when the input is kept as it is and nothing needs
/// saying).
pub(crate) fn auto_scale(
    units: InputUnits,
    kind: Option<&ObjectKind>,
    largest_side_m: f64,
) -> (f64, Option<String>) {
    if !(largest_side_m.is_finite() && largest_side_m > 0.0) {
        return (1.0, None);
    }
    match (units, kind) {
        (InputUnits::Normalised, Some(kind)) => {
            let factor = kind.prior.largest_side_m / largest_side_m;
            let note = format!(
                "unit auto: the input's coordinates are normalised (a PartNet-Mobility folder), so the object was scaled by {factor:.4} to the {:.2} m largest side typical of a {} ({}); give --unit to override",
                kind.prior.largest_side_m,
                kind.prior.noun(),
                kind.evidence
            );
            (factor, Some(note))
        }
        (InputUnits::Normalised, None) => (
            1.0,
            Some(
                "unit auto: the input's coordinates are normalised (a PartNet-Mobility folder) and nothing names the object's kind, so 1 unit was taken as 1 m; give --unit, or a meta.json with model_cat, for a real size"
                    .to_owned(),
            ),
        ),
        (_, Some(kind)) => {
            let typical = kind.prior.largest_side_m;
            let off = |metres_per_unit: f64| (largest_side_m * metres_per_unit / typical).ln().abs();
            if off(1.0) <= IMPLAUSIBLE_FACTOR.ln() {
                return (1.0, None);
            }
            let (unit, factor) = COMMON_UNITS
                .iter()
                .copied()
                .min_by(|a, b| off(a.1).total_cmp(&off(b.1)))
                .unwrap_or(("m", 1.0));
            if unit == "m" {
                return (1.0, None);
            }
            let note = format!(
                "unit auto: read as metres the object's largest side would be {largest_side_m:.3} m, implausible for a {} (typically {typical:.2} m; {}), so the input was read in {unit} ({} units); give --unit to override",
                kind.prior.noun(),
                kind.evidence,
                units.as_str()
            );
            (factor, Some(note))
        }
        (_, None) => (1.0, None),
    }
}

#[cfg(test)]
mod tests {
    use uniphys_ground::object_kind;

    use super::*;

    #[test]
    fn a_normalised_refrigerator_gets_the_typical_height() {
        let kind = object_kind(Some("Refrigerator"), "x", &[], &[]);
        let (factor, note) = auto_scale(InputUnits::Normalised, kind.as_ref(), 1.4);
        assert!((factor * 1.4 - 1.75).abs() < 1e-12);
        assert!(note.unwrap().contains("refrigerator"));
        let (factor, note) = auto_scale(InputUnits::Normalised, None, 1.4);
        assert_eq!(factor, 1.0);
        assert!(note.unwrap().contains("1 unit was taken as 1 m"));
    }

    #[test]
    fn a_plausible_size_in_metres_is_kept_and_an_implausible_one_takes_the_unit_that_fits() {
        let mug = object_kind(None, "mug", &[], &[]);
        assert_eq!(
            auto_scale(InputUnits::Unitless, mug.as_ref(), 0.11),
            (1.0, None)
        );
        let (factor, note) = auto_scale(InputUnits::Unitless, mug.as_ref(), 110.0);
        assert_eq!(factor, 0.001);
        assert!(note.unwrap().contains("read in mm"));
        let (factor, _) = auto_scale(InputUnits::Declared, mug.as_ref(), 11.0);
        assert_eq!(factor, 0.01);
        // No kind: nothing to judge the size by.
        assert_eq!(auto_scale(InputUnits::Unitless, None, 110.0), (1.0, None));
    }
}
