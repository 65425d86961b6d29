//! Choosing a part's material from its material and part names.

use uniphys_types::{Material, MaterialCategory, Provenance};

use crate::BUILTIN_PROVIDER;
use crate::keywords::{first_match, tokens};

/// Keywords per category, checked in this order (so `glass` wins over `metal` for `glass_frame`
/// only if no earlier category matched; the order puts specific materials first).
const CATEGORY_KEYWORDS: [(MaterialCategory, &[&str]); 11] = [
    (
        MaterialCategory::Rubber,
        &["rubber", "silicone", "latex", "tire", "tyre"],
    ),
    (MaterialCategory::Foam, &["foam", "sponge"]),
    (MaterialCategory::Leather, &["leather", "suede"]),
    (
        MaterialCategory::Fabric,
        &[
            "fabric",
            "cloth",
            "textile",
            "cotton",
            "linen",
            "wool",
            "canvas",
            "velvet",
            "polyester",
        ],
    ),
    (
        MaterialCategory::Glass,
        &["glass", "mirror", "lens", "crystal"],
    ),
    (
        MaterialCategory::Ceramics,
        &[
            "ceramic",
            "porcelain",
            "clay",
            "terracotta",
            "tile",
            "stoneware",
        ],
    ),
    (
        MaterialCategory::Stone,
        &["stone", "marble", "granite", "rock", "slate"],
    ),
    (MaterialCategory::Concrete, &["concrete", "cement"]),
    (
        MaterialCategory::Wood,
        &[
            "wood", "oak", "pine", "walnut", "maple", "birch", "plywood", "mdf", "bamboo",
            "timber", "cherry", "beech",
        ],
    ),
    (
        MaterialCategory::Metal,
        &[
            "metal",
            "steel",
            "iron",
            "aluminium",
            "aluminum",
            "alu",
            "brass",
            "copper",
            "chrome",
            "silver",
            "gold",
            "zinc",
            "titanium",
            "bronze",
            "tin",
        ],
    ),
    (
        MaterialCategory::Plastic,
        &[
            "plastic",
            "abs",
            "pvc",
            "nylon",
            "polymer",
            "acrylic",
            "polycarbonate",
            "resin",
            "vinyl",
        ],
    ),
];

/// Part-name fallbacks used when no material name says anything.
const PART_NAME_HINTS: [(MaterialCategory, &[&str]); 5] = [
    (
        MaterialCategory::Glass,
        &["screen", "display", "window", "pane"],
    ),
    (
        MaterialCategory::Rubber,
        &["wheel", "tire", "tyre", "foot", "feet", "grip"],
    ),
    (
        MaterialCategory::Fabric,
        &["cushion", "pillow", "curtain", "seat"],
    ),
    (
        MaterialCategory::Metal,
        &["handle", "knob", "hinge", "screw", "bolt", "rail", "leg"],
    ),
    (
        MaterialCategory::Wood,
        &[
            "cabinet", "drawer", "door", "shelf", "table", "desk", "drawer",
        ],
    ),
];

/// The material the built-in grounder assigns, with its provenance.
pub(crate) fn guess_material(material_names: &[&str], part_name: &str) -> (Material, Provenance) {
    for name in material_names {
        let toks = tokens(name);
        for (category, keywords) in CATEGORY_KEYWORDS {
            if let Some(keyword) = first_match(&toks, keywords) {
                let subtype = if keyword == category.as_str() {
                    toks.iter()
                        .find(|t| !t.starts_with(keyword) && t.chars().all(char::is_alphabetic))
                        .cloned()
                        .unwrap_or_default()
                } else {
                    keyword.to_owned()
                };
                return (
                    Material { category, subtype },
                    Provenance::provider(
                        BUILTIN_PROVIDER,
                        format!("material name {name:?} matched {keyword:?}"),
                    ),
                );
            }
        }
    }
    let toks = tokens(part_name);
    for (category, keywords) in PART_NAME_HINTS.iter().chain(CATEGORY_KEYWORDS.iter()) {
        if let Some(keyword) = first_match(&toks, keywords) {
            return (
                Material {
                    category: *category,
                    subtype: String::new(),
                },
                Provenance::provider(
                    BUILTIN_PROVIDER,
                    format!("part name {part_name:?} suggests {keyword:?}"),
                ),
            );
        }
    }
    (
        Material {
            category: MaterialCategory::Plastic,
            subtype: String::new(),
        },
        Provenance::default_because(
            "no material or part name gave evidence; plastic is the most common material of household objects",
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn material_names_win_over_part_names() {
        let (m, p) = guess_material(&["wood_oak"], "door_handle");
        assert_eq!(m.category, MaterialCategory::Wood);
        assert_eq!(m.subtype, "oak");
        assert!(matches!(p, Provenance::Provider { .. }));
        let (m, _) = guess_material(&["Material.001", "metal_steel"], "door");
        assert_eq!(
            (m.category, m.subtype.as_str()),
            (MaterialCategory::Metal, "steel")
        );
    }

    #[test]
    fn part_names_are_a_fallback_and_plastic_the_labelled_default() {
        assert_eq!(
            guess_material(&["Material.001"], "door_handle").0.category,
            MaterialCategory::Metal
        );
        assert_eq!(
            guess_material(&[], "lcd_screen").0.category,
            MaterialCategory::Glass
        );
        let (m, p) = guess_material(&[], "blob");
        assert_eq!(m.category, MaterialCategory::Plastic);
        assert!(matches!(p, Provenance::Default { .. }));
    }
}
