//! Choosing a part's material from its material and part names.

use uniphys_types::{Material, MaterialCategory, Provenance};

use crate::BUILTIN_PROVIDER;
use crate::object::ObjectKind;
use uniphys_types::words::{first_match, tokens};

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

/// Part-name words that name a panel of the object's body: such a part is made of what the body
/// is when the object's kind is known (a refrigerator's door is steel, a cabinet's is wood).
const BODY_PANEL_WORDS: [&str; 6] = ["cabinet", "drawer", "door", "shelf", "table", "desk"];

/// The material the built-in grounder assigns, with its provenance: from the material names,
/// else the part name, else the body material of the object's kind, else plastic.
pub(crate) fn guess_material(
    material_names: &[&str],
    part_name: &str,
    kind: Option<&ObjectKind>,
) -> (Material, Provenance) {
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
    let names_body_panel = first_match(&toks, &BODY_PANEL_WORDS).is_some();
    for (category, keywords) in PART_NAME_HINTS.iter().chain(CATEGORY_KEYWORDS.iter()) {
        if names_body_panel && kind.is_some() && *category == MaterialCategory::Wood {
            // The panel words' own hint (wood) gives way to the kind; a material word in the
            // name (`metal_drawer`) still counts.
            continue;
        }
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
    if let Some(kind) = kind {
        let (category, subtype) = kind.prior.body_material;
        return (
            Material {
                category,
                subtype: subtype.to_owned(),
            },
            Provenance::provider(
                BUILTIN_PROVIDER,
                format!(
                    "no name gave the material; the body of a {} is usually {} ({})",
                    kind.prior.noun(),
                    category.as_str(),
                    kind.evidence
                ),
            ),
        );
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
        let (m, p) = guess_material(&["wood_oak"], "door_handle", None);
        assert_eq!(m.category, MaterialCategory::Wood);
        assert_eq!(m.subtype, "oak");
        assert!(matches!(p, Provenance::Provider { .. }));
        let (m, _) = guess_material(&["Material.001", "metal_steel"], "door", None);
        assert_eq!(
            (m.category, m.subtype.as_str()),
            (MaterialCategory::Metal, "steel")
        );
    }

    #[test]
    fn part_names_are_a_fallback_and_plastic_the_labelled_default() {
        assert_eq!(
            guess_material(&["Material.001"], "door_handle", None)
                .0
                .category,
            MaterialCategory::Metal
        );
        assert_eq!(
            guess_material(&[], "lcd_screen", None).0.category,
            MaterialCategory::Glass
        );
        let (m, p) = guess_material(&[], "blob", None);
        assert_eq!(m.category, MaterialCategory::Plastic);
        assert!(matches!(p, Provenance::Default { .. }));
    }

    #[test]
    fn the_kind_gives_the_body_material_when_no_name_does() {
        let fridge = crate::object_kind(Some("Refrigerator"), "x", &[], &[]);
        let (m, p) = guess_material(&["material_0"], "link_3", fridge.as_ref());
        assert_eq!(
            (m.category, m.subtype.as_str()),
            (MaterialCategory::Metal, "steel")
        );
        assert!(format!("{p:?}").contains("refrigerator"), "{p:?}");
        // A door takes the body's material; a wheel or a handle keeps its own.
        let (m, _) = guess_material(&[], "door_1", fridge.as_ref());
        assert_eq!(m.category, MaterialCategory::Metal);
        assert_eq!(
            guess_material(&[], "door_1", None).0.category,
            MaterialCategory::Wood
        );
        let (m, _) = guess_material(&[], "wheel_2", fridge.as_ref());
        assert_eq!(m.category, MaterialCategory::Rubber);
        // A material word in a panel's name wins over the body.
        let (m, _) = guess_material(&[], "glass_door", fridge.as_ref());
        assert_eq!(m.category, MaterialCategory::Glass);
        let cabinet = crate::object_kind(Some("StorageFurniture"), "x", &[], &[]);
        let (m, _) = guess_material(&[], "metal_drawer", cabinet.as_ref());
        assert_eq!(m.category, MaterialCategory::Metal);
    }
}
