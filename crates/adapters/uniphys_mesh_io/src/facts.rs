//! What an input says about its object beyond the geometry: whether its coordinates have a
//! known unit, and the object's kind when a PartNet-Mobility folder's `meta.json` names it.

use std::path::Path;

use uniphys_types::SourceFormat;

/// How far the input's coordinates can be trusted as a length unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InputUnits {
    /// The format fixes the unit (glTF and URDF: metres).
    Declared,
    /// The format has no unit (OBJ, PLY, STL); metres by convention.
    Unitless,
    /// A PartNet-Mobility folder: coordinates normalised so that the largest side is about 1 to
    /// 2, not a length.
    Normalised,
}

impl InputUnits {
    /// Stable lower-case name for notes.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Declared => "declared",
            Self::Unitless => "unitless",
            Self::Normalised => "normalised",
        }
    }
}

/// Facts about the object that come with the input.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputFacts {
    /// Whether the coordinates have a known unit.
    pub units: InputUnits,
    /// The object's kind as the input names it (`meta.json`'s `model_cat`), if it does.
    pub declared_category: Option<String>,
}

/// The facts of the input whose main file is `main`, with warnings for what could not be read.
pub(crate) fn input_facts(
    main: &Path,
    format: SourceFormat,
    warnings: &mut Vec<String>,
) -> InputFacts {
    let dir = main.parent().unwrap_or(Path::new("."));
    let meta = dir.join("meta.json");
    let partnet = format == SourceFormat::Urdf
        && (meta.is_file()
            || dir.join("textured_objs").is_dir()
            || main.file_name().is_some_and(|n| n == "mobility.urdf"));
    let units = match format {
        _ if partnet => InputUnits::Normalised,
        SourceFormat::Glb | SourceFormat::Gltf | SourceFormat::Urdf => InputUnits::Declared,
        SourceFormat::Obj | SourceFormat::Ply | SourceFormat::Stl => InputUnits::Unitless,
    };
    let declared_category = if meta.is_file() {
        match read_model_category(&meta) {
            Ok(category) => category,
            Err(why) => {
                warnings.push(format!(
                    "meta.json next to the URDF was not used ({why}); the object's kind comes from names"
                ));
                None
            }
        }
    } else {
        None
    };
    InputFacts {
        units,
        declared_category,
    }
}

/// Largest `meta.json` read; PartNet-Mobility's are about 200 bytes.
const MAX_META_BYTES: u64 = 1 << 16;

fn read_model_category(meta: &Path) -> Result<Option<String>, String> {
    let size = std::fs::metadata(meta).map_err(|e| e.to_string())?.len();
    if size > MAX_META_BYTES {
        return Err(format!("{size} bytes, more than {MAX_META_BYTES}"));
    }
    let text = std::fs::read_to_string(meta).map_err(|e| e.to_string())?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("not JSON: {e}"))?;
    Ok(value
        .get("model_cat")
        .and_then(serde_json::Value::as_str)
        .map(str::trim)
        .filter(|c| !c.is_empty())
        .map(str::to_owned))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_partnet_folder_has_normalised_units_and_its_meta_category() {
        let dir = tempfile::tempdir().unwrap();
        let urdf = dir.path().join("mobility.urdf");
        std::fs::write(&urdf, "<robot/>").unwrap();
        let mut warnings = Vec::new();
        let facts = input_facts(&urdf, SourceFormat::Urdf, &mut warnings);
        assert_eq!(facts.units, InputUnits::Normalised);
        assert_eq!(facts.declared_category, None);
        std::fs::write(
            dir.path().join("meta.json"),
            r#"{"model_id": "x", "model_cat": "Refrigerator"}"#,
        )
        .unwrap();
        let facts = input_facts(&urdf, SourceFormat::Urdf, &mut warnings);
        assert_eq!(facts.declared_category.as_deref(), Some("Refrigerator"));
        assert!(warnings.is_empty());
        std::fs::write(dir.path().join("meta.json"), "{oops").unwrap();
        let facts = input_facts(&urdf, SourceFormat::Urdf, &mut warnings);
        assert_eq!(facts.declared_category, None);
        assert!(warnings[0].contains("not JSON"), "{warnings:?}");
    }

    #[test]
    fn other_inputs_have_declared_or_no_units() {
        let dir = tempfile::tempdir().unwrap();
        let mut warnings = Vec::new();
        let robot = dir.path().join("robot.urdf");
        let facts = input_facts(&robot, SourceFormat::Urdf, &mut warnings);
        assert_eq!(facts.units, InputUnits::Declared);
        let mesh = dir.path().join("mug.obj");
        assert_eq!(
            input_facts(&mesh, SourceFormat::Obj, &mut warnings).units,
            InputUnits::Unitless
        );
        assert_eq!(
            input_facts(&mesh, SourceFormat::Glb, &mut warnings).units,
            InputUnits::Declared
        );
    }
}
