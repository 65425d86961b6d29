//! The list of examples, lookup by name, and writing them all as GLB files.

use std::path::{Path, PathBuf};

use crate::box_with_lid::box_with_lid;
use crate::cabinet::cabinet;
use crate::laptop::laptop;
use crate::mug::mug;
use crate::{ExampleAsset, ExamplesError, GlbFrame, write_glb};

/// Names of all examples, sorted.
pub const EXAMPLE_NAMES: [&str; 4] = ["box_with_lid", "cabinet", "laptop", "mug"];

/// All examples, sorted by name.
#[must_use]
pub fn catalogue() -> Vec<ExampleAsset> {
    EXAMPLE_NAMES
        .iter()
        .filter_map(|name| example(name))
        .collect()
}

/// The example called `name`, if there is one.
#[must_use]
pub fn example(name: &str) -> Option<ExampleAsset> {
    match name {
        "box_with_lid" => Some(box_with_lid()),
        "cabinet" => Some(cabinet()),
        "laptop" => Some(laptop()),
        "mug" => Some(mug()),
        _ => None,
    }
}

/// Writes every example as `<dir>/<name>.glb` (Y up, as glTF files normally are), creating `dir`
/// if needed, and returns the paths in catalogue order.
///
/// # Errors
/// [`ExamplesError::Io`] if the directory or a file cannot be written, or an error of
/// [`write_glb`].
pub fn write_catalogue(dir: &Path) -> Result<Vec<PathBuf>, ExamplesError> {
    std::fs::create_dir_all(dir).map_err(|source| ExamplesError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    catalogue()
        .iter()
        .map(|example| {
            let path = dir.join(format!("{}.glb", example.name));
            let bytes = write_glb(&example.asset, GlbFrame::YUp)?;
            std::fs::write(&path, bytes).map_err(|source| ExamplesError::Io {
                path: path.clone(),
                source,
            })?;
            Ok(path)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_is_sorted_by_name_and_matches_lookup() {
        let names: Vec<&str> = catalogue().iter().map(|e| e.name).collect();
        assert_eq!(names, EXAMPLE_NAMES);
        let mut sorted = names.clone();
        sorted.sort_unstable();
        assert_eq!(names, sorted);
        for name in EXAMPLE_NAMES {
            assert_eq!(example(name).map(|e| e.name), Some(name));
        }
        assert!(example("sofa").is_none());
    }
}
