//! Object-level properties: name, category, dimensions and mass.

use uniphys_types::{Estimate, ObjectProperties, Provenance};

use crate::BUILTIN_PROVIDER;
use crate::keywords::{first_match, tokens};

/// Categories of the reference taxonomy for common object names: (keywords, `Category/Subcategory`).
const CATEGORIES: [(&[&str], &str); 12] = [
    (
        &[
            "cabinet", "wardrobe", "dresser", "drawer", "cupboard", "shelf", "bookcase",
        ],
        "Furniture/StorageFurniture",
    ),
    (&["table", "desk"], "Furniture/TableFurniture"),
    (
        &["chair", "sofa", "stool", "bench"],
        "Furniture/SeatingFurniture",
    ),
    (
        &["door", "window"],
        "ArchitecturalBuilding/DoorWindowElement",
    ),
    (
        &["laptop", "computer", "monitor", "keyboard", "mouse"],
        "ElectronicsDevices/ComputerPeripheral",
    ),
    (
        &["phone", "tablet", "camera", "radio", "remote"],
        "ElectronicsDevices/ConsumerElectronics",
    ),
    (
        &[
            "mug", "cup", "glass", "bottle", "bowl", "plate", "kettle", "teapot", "jar",
        ],
        "KitchenDining/TablewareDrinkware",
    ),
    (
        &[
            "microwave",
            "oven",
            "fridge",
            "refrigerator",
            "dishwasher",
            "toaster",
        ],
        "KitchenDining/KitchenAppliance",
    ),
    (
        &[
            "box",
            "crate",
            "chest",
            "case",
            "bin",
            "basket",
            "container",
        ],
        "ContainersStorage/GeneralContainer",
    ),
    (
        &["faucet", "toilet", "sink"],
        "PlumbingSanitary/PlumbingFixture",
    ),
    (&["lamp", "light"], "LightingElectrical/IndoorLighting"),
    (
        &["scissors", "pliers", "hammer", "wrench", "stapler"],
        "ToolsEquipment/HandTool",
    ),
];

/// Object properties from the asset name, the part names, bounds and part masses.
#[must_use]
pub fn object_properties(
    asset_name: &str,
    part_names: &[&str],
    dimensions_m: [f64; 3],
    part_masses_kg: &[f64],
) -> ObjectProperties {
    let name_tokens = tokens(asset_name);
    let all_tokens: Vec<String> = name_tokens
        .iter()
        .cloned()
        .chain(part_names.iter().flat_map(|n| tokens(n)))
        .collect();
    let category = CATEGORIES
        .iter()
        .find_map(|(keys, cat)| first_match(&name_tokens, keys).map(|k| (k, *cat, "asset name")))
        .or_else(|| {
            CATEGORIES.iter().find_map(|(keys, cat)| {
                first_match(&all_tokens, keys).map(|k| (k, *cat, "part names"))
            })
        });
    let category = match category {
        Some((keyword, cat, source)) => Estimate::new(
            cat.to_owned(),
            Provenance::provider(BUILTIN_PROVIDER, format!("{source} suggest {keyword:?}")),
        ),
        None => Estimate::new(
            "OtherMiscellaneous/OtherObject".to_owned(),
            Provenance::default_because("no known object word in the asset or part names"),
        ),
    };
    let display_name = name_tokens
        .iter()
        .filter(|t| t.chars().any(char::is_alphabetic))
        .cloned()
        .collect::<Vec<_>>()
        .join(" ");
    ObjectProperties {
        name: Estimate::new(
            if display_name.is_empty() {
                "object".to_owned()
            } else {
                display_name
            },
            Provenance::input("asset file name"),
        ),
        category,
        dimensions_m: Estimate::new(dimensions_m, Provenance::rule("bounds_of_parts")),
        mass_kg: Estimate::new(
            part_masses_kg.iter().sum(),
            Provenance::rule("sum_of_part_density_times_volume"),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn category_comes_from_the_asset_name_before_part_names() {
        let o = object_properties(
            "my_Laptop-02",
            &["lid", "drawer"],
            [0.3, 0.2, 0.1],
            &[1.0, 0.5],
        );
        assert_eq!(o.category.value, "ElectronicsDevices/ComputerPeripheral");
        assert_eq!(o.name.value, "my laptop");
        assert!((o.mass_kg.value - 1.5).abs() < 1e-12);
        let o = object_properties("asset_17", &["drawer"], [1.0; 3], &[]);
        assert_eq!(o.category.value, "Furniture/StorageFurniture");
        let o = object_properties("blob", &["thing"], [1.0; 3], &[]);
        assert!(matches!(o.category.provenance, Provenance::Default { .. }));
    }
}
