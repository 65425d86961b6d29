//! The object folders of a PartNet-Mobility set, shared by the benchmarks that read one.

use std::path::{Path, PathBuf};

use anyhow::Context;

/// The sub-folders of `root` that hold a `mobility.urdf` and whose folder name `keep` accepts,
/// sorted by path.
pub(crate) fn object_dirs(
    root: &Path,
    keep: &dyn Fn(&str) -> bool,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(root)
        .with_context(|| format!("failed to list {}", root.display()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.join("mobility.urdf").is_file())
        .filter(|p| keep(&folder_name(p)))
        .collect();
    dirs.sort();
    Ok(dirs)
}

/// The last component of `dir` (an object's folder name), empty if it has none.
pub(crate) fn folder_name(dir: &Path) -> String {
    dir.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
