//! Kinds of objects with the size, mass and body material of typical real ones: the priors that
//! give an asset in unknown units a real size (`--unit auto`), its unnamed parts a material, and
//! verification a band to judge the result against. Sources: `docs/object-categories.md`.

use crate::MaterialCategory;
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

use MaterialCategory::{Ceramics, Metal, Plastic, Wood};

const fn row(
    name: &'static str,
    taxonomy: &'static str,
    keywords: &'static [&'static str],
    largest_side_m: f64,
    mass_kg: f64,
    body_material: (MaterialCategory, &'static str),
    interior_fill: f64,
) -> CategoryPrior {
    CategoryPrior {
        name,
        taxonomy,
        keywords,
        largest_side_m,
        mass_kg,
        body_material,
        interior_fill,
    }
}

/// The kinds of household objects, PartNet-Mobility's 46 and ten common others, checked in
/// this order (specific kinds before general ones). Figures: `docs/object-categories.md`.
pub const CATEGORY_PRIORS: [CategoryPrior; 56] = [
    row(
        "Refrigerator",
        "KitchenDining/KitchenAppliance",
        &["refrigerator", "fridge", "freezer"],
        1.75,
        80.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Dishwasher",
        "KitchenDining/KitchenAppliance",
        &["dishwasher"],
        0.85,
        45.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "WashingMachine",
        "KitchenDining/KitchenAppliance",
        &["washing", "washer", "dryer"],
        0.85,
        70.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Microwave",
        "KitchenDining/KitchenAppliance",
        &["microwave"],
        0.5,
        13.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Oven",
        "KitchenDining/KitchenAppliance",
        &["oven", "stove", "range", "cooker"],
        0.75,
        40.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Toaster",
        "KitchenDining/KitchenAppliance",
        &["toaster"],
        0.3,
        2.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "CoffeeMachine",
        "KitchenDining/KitchenAppliance",
        &["coffee", "espresso"],
        0.4,
        5.0,
        (Plastic, "abs"),
        HOLLOW,
    ),
    row(
        "Kettle",
        "KitchenDining/KitchenAppliance",
        &["kettle", "teapot"],
        0.25,
        1.2,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "KitchenPot",
        "KitchenDining/CookwareUtensil",
        &["pot", "saucepan", "casserole", "pan"],
        0.3,
        1.5,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Knife",
        "KitchenDining/CookwareUtensil",
        &["knife", "blade", "cleaver"],
        0.25,
        0.15,
        (Metal, "steel"),
        SOLID,
    ),
    row(
        "Bottle",
        "KitchenDining/TablewareDrinkware",
        &["bottle", "flask", "jar"],
        0.3,
        0.4,
        (Plastic, ""),
        HOLLOW,
    ),
    row(
        "Mug",
        "KitchenDining/TablewareDrinkware",
        &["mug", "cup"],
        0.12,
        0.35,
        (Ceramics, "porcelain"),
        HOLLOW,
    ),
    row(
        "Bowl",
        "KitchenDining/TablewareDrinkware",
        &["bowl"],
        0.18,
        0.4,
        (Ceramics, "porcelain"),
        HOLLOW,
    ),
    row(
        "Plate",
        "KitchenDining/TablewareDrinkware",
        &["plate"],
        0.27,
        0.55,
        (Ceramics, "porcelain"),
        HOLLOW,
    ),
    row(
        "Dispenser",
        "PlumbingSanitary/BathroomAccessory",
        &["dispenser", "soap"],
        0.2,
        0.3,
        (Plastic, ""),
        HOLLOW,
    ),
    row(
        "Faucet",
        "PlumbingSanitary/PlumbingFixture",
        &["faucet", "tap"],
        0.3,
        1.5,
        (Metal, "brass"),
        HOLLOW,
    ),
    row(
        "Toilet",
        "PlumbingSanitary/PlumbingFixture",
        &["toilet"],
        0.7,
        40.0,
        (Ceramics, "porcelain"),
        HOLLOW,
    ),
    row(
        "Sink",
        "PlumbingSanitary/PlumbingFixture",
        &["sink", "basin"],
        0.6,
        12.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "StorageFurniture",
        "Furniture/StorageFurniture",
        &[
            "cabinet",
            "wardrobe",
            "dresser",
            "drawer",
            "cupboard",
            "shelf",
            "bookcase",
            "sideboard",
        ],
        1.0,
        35.0,
        (Wood, ""),
        HOLLOW,
    ),
    row(
        "Table",
        "Furniture/TableFurniture",
        &["table", "desk"],
        1.2,
        35.0,
        (Wood, ""),
        HOLLOW,
    ),
    row(
        "FoldingChair",
        "Furniture/SeatingFurniture",
        &["folding"],
        0.85,
        4.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Chair",
        "Furniture/SeatingFurniture",
        &["chair", "stool", "seat"],
        0.9,
        7.0,
        (Wood, ""),
        HOLLOW,
    ),
    row(
        "Safe",
        "ContainersStorage/GeneralContainer",
        &["safe", "strongbox"],
        0.5,
        40.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "TrashCan",
        "ContainersStorage/WasteRecyclingContainer",
        &["trash", "garbage", "bin", "wastebasket", "dustbin"],
        0.6,
        3.0,
        (Plastic, ""),
        HOLLOW,
    ),
    row(
        "Bucket",
        "ContainersStorage/StorageVessel",
        &["bucket", "pail"],
        0.35,
        1.0,
        (Plastic, ""),
        HOLLOW,
    ),
    row(
        "Suitcase",
        "ApparelWearables/LuggageBag",
        &["suitcase", "luggage"],
        0.65,
        4.0,
        (Plastic, "abs"),
        HOLLOW,
    ),
    row(
        "Box",
        "ContainersStorage/GeneralContainer",
        &["box", "crate", "chest", "case", "basket", "container"],
        0.4,
        1.5,
        (Wood, ""),
        HOLLOW,
    ),
    row(
        "Laptop",
        "ElectronicsDevices/ComputerPeripheral",
        &["laptop", "notebook"],
        0.35,
        2.0,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Display",
        "ElectronicsDevices/ComputerPeripheral",
        &["display", "monitor", "screen", "tv"],
        0.6,
        5.0,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Keyboard",
        "ElectronicsDevices/ComputerPeripheral",
        &["keyboard"],
        0.45,
        0.8,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Mouse",
        "ElectronicsDevices/ComputerPeripheral",
        &["mouse"],
        0.11,
        0.1,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Printer",
        "ElectronicsDevices/ComputerPeripheral",
        &["printer", "scanner"],
        0.45,
        8.0,
        (Plastic, "abs"),
        HOLLOW,
    ),
    row(
        "Computer",
        "ElectronicsDevices/ComputerPeripheral",
        &["computer", "pc"],
        0.45,
        8.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "USB",
        "ElectronicsDevices/ComputerPeripheral",
        &["usb"],
        0.06,
        0.01,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Camera",
        "ElectronicsDevices/ConsumerElectronics",
        &["camera"],
        0.15,
        0.6,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Phone",
        "ElectronicsDevices/CommunicationDevice",
        &["phone", "smartphone", "telephone"],
        0.15,
        0.18,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Tablet",
        "ElectronicsDevices/ConsumerElectronics",
        &["tablet", "ipad"],
        0.25,
        0.5,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Remote",
        "ElectronicsDevices/ControlInputDevice",
        &["remote"],
        0.18,
        0.12,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Radio",
        "ElectronicsDevices/ConsumerElectronics",
        &["radio"],
        0.25,
        1.0,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Switch",
        "LightingElectrical/ElectricalFixture",
        &["switch"],
        0.1,
        0.05,
        (Plastic, "abs"),
        PACKED,
    ),
    row(
        "Fan",
        "ElectronicsDevices/Electronics_Other",
        &["fan"],
        0.5,
        3.0,
        (Plastic, "abs"),
        HOLLOW,
    ),
    row(
        "Clock",
        "OtherMiscellaneous/OtherObject",
        &["clock"],
        0.3,
        1.0,
        (Plastic, "abs"),
        HOLLOW,
    ),
    row(
        "Lighter",
        "OtherMiscellaneous/OtherObject",
        &["lighter"],
        0.08,
        0.02,
        (Plastic, ""),
        PACKED,
    ),
    row(
        "Lamp",
        "LightingElectrical/IndoorLighting",
        &["lamp", "light"],
        0.5,
        1.5,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Door",
        "ArchitecturalBuilding/DoorWindowElement",
        &["door"],
        2.0,
        30.0,
        (Wood, ""),
        HOLLOW,
    ),
    row(
        "Window",
        "ArchitecturalBuilding/DoorWindowElement",
        &["window"],
        1.2,
        20.0,
        (Wood, ""),
        HOLLOW,
    ),
    row(
        "Globe",
        "ToysFiguresModels/EducationalModel",
        &["globe"],
        0.4,
        1.5,
        (Plastic, ""),
        HOLLOW,
    ),
    row(
        "Eyeglasses",
        "ApparelWearables/PersonalAccessory",
        &["eyeglasses", "glasses", "spectacles", "sunglasses"],
        0.14,
        0.03,
        (Plastic, ""),
        SOLID,
    ),
    row(
        "Pen",
        "OtherMiscellaneous/OtherObject",
        &["pen", "pencil", "marker"],
        0.14,
        0.015,
        (Plastic, ""),
        PACKED,
    ),
    row(
        "Scissors",
        "ToolsEquipment/HandTool",
        &["scissors", "shears"],
        0.2,
        0.1,
        (Metal, "steel"),
        SOLID,
    ),
    row(
        "Pliers",
        "ToolsEquipment/HandTool",
        &["pliers"],
        0.2,
        0.25,
        (Metal, "steel"),
        SOLID,
    ),
    row(
        "Stapler",
        "ToolsEquipment/HandTool",
        &["stapler"],
        0.17,
        0.3,
        (Metal, "steel"),
        PACKED,
    ),
    row(
        "Hammer",
        "ToolsEquipment/HandTool",
        &["hammer", "mallet"],
        0.33,
        0.6,
        (Metal, "steel"),
        SOLID,
    ),
    row(
        "Wrench",
        "ToolsEquipment/HandTool",
        &["wrench", "spanner"],
        0.25,
        0.3,
        (Metal, "steel"),
        SOLID,
    ),
    row(
        "Cart",
        "VehiclesMobility/TransportAccessory",
        &["cart", "trolley", "wagon"],
        1.0,
        15.0,
        (Metal, "steel"),
        HOLLOW,
    ),
    row(
        "Sofa",
        "Furniture/SeatingFurniture",
        &["sofa", "couch", "bench"],
        2.0,
        45.0,
        (Wood, ""),
        HOLLOW,
    ),
];

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
