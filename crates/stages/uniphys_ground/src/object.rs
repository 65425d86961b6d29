//! Object-level properties: the object's kind (from everything the input names), name,
//! category, dimensions and mass.

use uniphys_types::words::{token_matches, tokens};
use uniphys_types::{CategoryPrior, Estimate, ObjectProperties, Provenance};

use crate::BUILTIN_PROVIDER;

/// The kind of an object and what said so.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectKind {
    /// The kind with its typical size, mass and body material.
    pub prior: &'static CategoryPrior,
    /// Where the kind came from, e.g. `meta.json names "Refrigerator"`.
    pub evidence: String,
}

/// Words that name a part of many kinds of object (a fridge's door, a fan's blade), so a part
/// so named says nothing about the object's kind.
const PART_WORDS: [&str; 9] = [
    "door", "window", "screen", "display", "switch", "blade", "light", "seat", "handle",
];

/// The object's kind from, in order of trust: the kind the input declares (a PartNet-Mobility
/// `meta.json`), the asset's name, its parts' names (words that name common parts of many kinds
/// excluded), its materials' names. `None` when nothing names a known kind.
#[must_use]
pub fn object_kind(
    declared: Option<&str>,
    asset_name: &str,
    part_names: &[&str],
    material_names: &[&str],
) -> Option<ObjectKind> {
    let kind = |prior, evidence| Some(ObjectKind { prior, evidence });
    if let Some(prior) = declared.and_then(CategoryPrior::by_name) {
        return kind(
            prior,
            format!("the input declares {:?}", declared.unwrap_or_default()),
        );
    }
    if let Some((prior, keyword)) = CategoryPrior::in_words(asset_name) {
        return kind(prior, format!("the asset name suggests {keyword:?}"));
    }
    for name in part_names {
        let toks: Vec<String> = tokens(name)
            .into_iter()
            .filter(|t| !PART_WORDS.iter().any(|w| token_matches(t, w)))
            .collect();
        if let Some((prior, keyword)) = CategoryPrior::in_tokens(&toks) {
            return kind(prior, format!("part name {name:?} suggests {keyword:?}"));
        }
    }
    material_names.iter().find_map(|name| {
        CategoryPrior::in_words(name)
            .and_then(|(prior, k)| kind(prior, format!("material name {name:?} suggests {k:?}")))
    })
}

/// Object properties from the asset name, the object's kind, bounds and part masses. The name
/// is the asset's file name in words, or the kind's when the file name does not name it (a
/// PartNet-Mobility folder is called by a number).
#[must_use]
pub fn object_properties(
    asset_name: &str,
    kind: Option<&ObjectKind>,
    dimensions_m: [f64; 3],
    part_masses_kg: &[f64],
) -> ObjectProperties {
    let category = match kind {
        Some(k) => Estimate::new(
            k.prior.taxonomy.to_owned(),
            Provenance::provider(BUILTIN_PROVIDER, k.evidence.clone()),
        ),
        None => Estimate::new(
            "OtherMiscellaneous/OtherObject".to_owned(),
            Provenance::default_because("nothing in the input names a known kind of object"),
        ),
    };
    let words: Vec<String> = tokens(asset_name)
        .into_iter()
        .filter(|t| t.chars().any(char::is_alphabetic))
        .collect();
    let names_kind = CategoryPrior::in_words(asset_name).is_some();
    let name = match kind {
        Some(k) if !names_kind => Estimate::new(
            k.prior.noun(),
            Provenance::provider(
                BUILTIN_PROVIDER,
                format!("the object's kind: {}", k.evidence),
            ),
        ),
        _ if words.is_empty() => Estimate::new(
            "object".to_owned(),
            Provenance::default_because("the file name has no word"),
        ),
        _ => Estimate::new(words.join(" "), Provenance::input("asset file name")),
    };
    ObjectProperties {
        name,
        category,
        dimensions_m: Estimate::new(dimensions_m, Provenance::rule("bounds_of_parts")),
        mass_kg: Estimate::new(
            part_masses_kg.iter().sum(),
            Provenance::rule("sum_of_part_masses"),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_declared_kind_wins_then_the_asset_name_then_part_and_material_names() {
        let k = object_kind(Some("Oven"), "my_Laptop-02", &["lid"], &[]).unwrap();
        assert_eq!(k.prior.name, "Oven");
        let k = object_kind(None, "my_Laptop-02", &["drawer"], &[]).unwrap();
        assert_eq!(k.prior.name, "Laptop");
        let k = object_kind(Some("Spaceship"), "asset_17", &["drawer_1"], &[]).unwrap();
        assert_eq!(k.prior.name, "StorageFurniture");
        assert!(k.evidence.contains("drawer_1"), "{}", k.evidence);
        let k = object_kind(None, "thing", &["part"], &["fridge_steel"]).unwrap();
        assert_eq!(k.prior.name, "Refrigerator");
        assert!(object_kind(None, "kitchen-11622", &["link_0"], &["material_0"]).is_none());
    }

    #[test]
    fn a_part_named_for_a_common_part_says_nothing_of_the_object() {
        assert!(object_kind(None, "asset", &["door_1", "screen", "handle"], &[]).is_none());
    }

    #[test]
    fn the_name_is_the_file_name_unless_only_the_kind_names_the_object() {
        let laptop = object_kind(None, "my_Laptop-02", &[], &[]);
        let o = object_properties(
            "my_Laptop-02",
            laptop.as_ref(),
            [0.3, 0.2, 0.1],
            &[1.0, 0.5],
        );
        assert_eq!(o.category.value, "ElectronicsDevices/ComputerPeripheral");
        assert_eq!(o.name.value, "my laptop");
        assert!((o.mass_kg.value - 1.5).abs() < 1e-12);
        let fridge = object_kind(Some("Refrigerator"), "kitchen-11622", &[], &[]);
        let o = object_properties("kitchen-11622", fridge.as_ref(), [1.0; 3], &[]);
        assert_eq!(o.name.value, "refrigerator");
        assert_eq!(o.category.value, "KitchenDining/KitchenAppliance");
        let o = object_properties("blob", None, [1.0; 3], &[]);
        assert_eq!(o.name.value, "blob");
        assert!(matches!(o.category.provenance, Provenance::Default { .. }));
    }
}
