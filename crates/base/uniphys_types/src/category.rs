//! Kinds of objects with the size, mass and body material of typical real ones: the priors that
//! give an asset in unknown units a real size (`--unit auto`), its unnamed parts a material, and
//! verification a band to judge the result against. The table itself is in `category_table.rs`;
//! sources: `docs/object-categories.md`.

use crate::MaterialCategory;
pub use crate::category_table::CATEGORY_PRIORS;
use crate::words::{first_match, tokens};

/// Real objects of a kind lie within typical ÷ f and typical × f of its typical mass.
pub const MASS_BAND_FACTOR: f64 = 3.0;
/// Real objects of a kind lie within typical ÷ f and typical × f of its typical largest side.
pub const SIZE_BAND_FACTOR: f64 = 2.0;

/// One kind of object and what real objects of that kind are like.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CategoryPrior {
    /// The kind as PartNet-Mobility's `meta.json` spells it (`model_cat`), e.g. `StorageFurniture`.
    pub name: &'static str,
    /// The reference taxonomy's `Category/Subcategory`.
    pub taxonomy: &'static str,
    /// Words in file, part or material names that name the kind (prefix match from 4 letters).
    pub keywords: &'static [&'static str],
    /// Typical largest side of the object's box, metres.
    pub largest_side_m: f64,
    /// Typical mass of the whole object, kg.
    pub mass_kg: f64,
    /// What the body is made of when no material or part name says otherwise: the material
    /// category and a subtype the grounder knows (`steel`, `brass`, `abs`) or empty.
    pub body_material: (MaterialCategory, &'static str),
    /// How much of what the walls enclose is filled with material: [`HOLLOW`] (appliances,
    /// furniture, containers), [`PACKED`] (devices full of components) or [`SOLID`] (tools,
    /// blades).
    pub interior_fill: f64,
}

/// Kinds whose walls enclose air: appliances, furniture, containers.
pub const HOLLOW: f64 = 0.0;
/// Kinds whose walls enclose components: electronics have a bulk density of about 0.4 to 0.6 of
/// the plastic they are made of.
pub const PACKED: f64 = 0.4;
/// Kinds that are solid through: blades, tools, frames.
pub const SOLID: f64 = 1.0;

impl CategoryPrior {
    /// The typical mass band, kg: typical ÷ [`MASS_BAND_FACTOR`] to typical × the factor.
    #[must_use]
    pub fn mass_band_kg(&self) -> [f64; 2] {
        [
            self.mass_kg / MASS_BAND_FACTOR,
            self.mass_kg * MASS_BAND_FACTOR,
        ]
    }

    /// The typical band of the largest side, m.
    #[must_use]
    pub fn largest_side_band_m(&self) -> [f64; 2] {
        [
            self.largest_side_m / SIZE_BAND_FACTOR,
            self.largest_side_m * SIZE_BAND_FACTOR,
        ]
    }

    /// The kind named `name` (`meta.json`'s `model_cat`, case and punctuation ignored), or one of
    /// its keywords as a whole word.
    #[must_use]
    pub fn by_name(name: &str) -> Option<&'static Self> {
        let wanted = squashed(name);
        if wanted.is_empty() {
            return None;
        }
        CATEGORY_PRIORS
            .iter()
            .find(|c| squashed(c.name) == wanted)
            .or_else(|| {
                CATEGORY_PRIORS
                    .iter()
                    .find(|c| c.keywords.iter().any(|k| *k == wanted))
            })
    }

    /// The first kind (in table order) one of whose keywords a word of `text` matches, with the
    /// keyword.
    #[must_use]
    pub fn in_words(text: &str) -> Option<(&'static Self, &'static str)> {
        Self::in_tokens(&tokens(text))
    }

    /// [`Self::in_words`] for words already split by [`crate::words::tokens`].
    #[must_use]
    pub fn in_tokens(toks: &[String]) -> Option<(&'static Self, &'static str)> {
        CATEGORY_PRIORS
            .iter()
            .find_map(|c| first_match(toks, c.keywords).map(|k| (c, k)))
    }

    /// The kind of a grounded object: the one its name names, else the only kind of its
    /// taxonomy category.
    #[must_use]
    pub fn of_object(name: &str, taxonomy: &str) -> Option<&'static Self> {
        if let Some((c, _)) = Self::in_words(name) {
            return Some(c);
        }
        let mut same = CATEGORY_PRIORS.iter().filter(|c| c.taxonomy == taxonomy);
        match (same.next(), same.next()) {
            (Some(only), None) => Some(only),
            _ => None,
        }
    }

    /// The kind's name in lower-case words (`StorageFurniture` -> `storage furniture`).
    #[must_use]
    pub fn noun(&self) -> String {
        tokens(self.name).join(" ")
    }
}

fn squashed(text: &str) -> String {
    text.chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_a_valid_taxonomy_pair_with_positive_figures_and_a_material_prior() {
        for c in &CATEGORY_PRIORS {
            let (category, sub) = c.taxonomy.split_once('/').expect("Category/Subcategory");
            assert!(!category.is_empty() && !sub.is_empty(), "{}", c.name);
            assert!(c.largest_side_m > 0.0 && c.mass_kg > 0.0, "{}", c.name);
            assert!(c.body_material.0.prior().is_some(), "{}", c.name);
            assert!(!c.keywords.is_empty(), "{}", c.name);
        }
        let mut names: Vec<&str> = CATEGORY_PRIORS.iter().map(|c| c.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), CATEGORY_PRIORS.len(), "kind names are unique");
    }

    #[test]
    fn kinds_are_found_by_meta_name_keyword_and_words() {
        assert_eq!(
            CategoryPrior::by_name("StorageFurniture").unwrap().name,
            "StorageFurniture"
        );
        assert_eq!(
            CategoryPrior::by_name("kitchen_pot").unwrap().name,
            "KitchenPot"
        );
        assert_eq!(
            CategoryPrior::by_name("fridge").unwrap().name,
            "Refrigerator"
        );
        assert!(CategoryPrior::by_name("").is_none());
        assert!(CategoryPrior::by_name("spaceship").is_none());
        let (c, k) = CategoryPrior::in_words("My_Fridge-02").unwrap();
        assert_eq!((c.name, k), ("Refrigerator", "fridge"));
        assert!(CategoryPrior::in_words("kitchen-11622").is_none());
        // Names the earlier keyword table knew keep a kind.
        for (name, kind) in [
            ("salad_bowl", "Bowl"),
            ("kitchen_sink", "Sink"),
            ("radio", "Radio"),
        ] {
            assert_eq!(
                CategoryPrior::in_words(name).unwrap().0.name,
                kind,
                "{name}"
            );
        }
    }

    #[test]
    fn a_grounded_object_finds_its_kind_by_name_or_by_a_taxonomy_only_one_kind_has() {
        let c = CategoryPrior::of_object("oven", "KitchenDining/KitchenAppliance").unwrap();
        assert_eq!(c.name, "Oven");
        let c = CategoryPrior::of_object("object", "Furniture/TableFurniture").unwrap();
        assert_eq!(c.name, "Table");
        assert!(CategoryPrior::of_object("object", "KitchenDining/KitchenAppliance").is_none());
        assert_eq!(CategoryPrior::by_name("Laptop").unwrap().noun(), "laptop");
        assert_eq!(
            CategoryPrior::by_name("StorageFurniture").unwrap().noun(),
            "storage furniture"
        );
    }

    #[test]
    fn bands_span_the_factors_around_the_typical_values() {
        let c = CategoryPrior::by_name("Laptop").unwrap();
        let [lo, hi] = c.mass_band_kg();
        assert!((lo * MASS_BAND_FACTOR - c.mass_kg).abs() < 1e-12);
        assert!((hi / MASS_BAND_FACTOR - c.mass_kg).abs() < 1e-12);
        let [lo, hi] = c.largest_side_band_m();
        assert!(lo < c.largest_side_m && c.largest_side_m < hi);
    }
}
