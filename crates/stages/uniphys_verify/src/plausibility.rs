//! Plausibility: the object against real objects of its kind. An asset whose mass or size lies
//! outside the band of its kind (`uniphys_types::CategoryPrior`) gets a warning that says by how
//! much, never a silent pass; it is not a failure, since real objects vary and the kind may be
//! wrong.

use uniphys_types::{AssetRecord, CategoryPrior, CheckOutcome, CheckResult};

/// The object's mass and largest side against its kind's bands; no check when the kind is not
/// known.
#[must_use]
pub fn plausibility_checks(record: &AssetRecord) -> Vec<CheckResult> {
    let object = &record.object;
    let Some(kind) = CategoryPrior::of_object(&object.name.value, &object.category.value) else {
        return Vec::new();
    };
    let noun = kind.noun();
    let mass_kg = object.mass_kg.value;
    let largest_side_m = object
        .dimensions_m
        .value
        .iter()
        .copied()
        .fold(0.0, f64::max);
    let judge = |what: &str, value: f64, unit: &str, typical: f64, band: [f64; 2]| {
        let inside = value >= band[0] && value <= band[1];
        CheckResult {
            check: "plausibility".to_owned(),
            subject: "object".to_owned(),
            outcome: if inside {
                CheckOutcome::Pass
            } else {
                CheckOutcome::Warn
            },
            message: format!(
                "{what} {value:.3} {unit} is {:.2} times the typical {typical} {unit} of a {noun}{}",
                value / typical,
                if inside {
                    format!(" (band {:.3}-{:.3})", band[0], band[1])
                } else {
                    format!(
                        ", outside the band of real ones ({:.3}-{:.3}): check the unit, the materials and whether the parts are solid or hollow",
                        band[0], band[1]
                    )
                }
            ),
        }
    };
    vec![
        judge("mass", mass_kg, "kg", kind.mass_kg, kind.mass_band_kg()),
        judge(
            "largest side",
            largest_side_m,
            "m",
            kind.largest_side_m,
            kind.largest_side_band_m(),
        ),
    ]
}
