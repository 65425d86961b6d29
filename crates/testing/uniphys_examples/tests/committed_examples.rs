//! The GLB files committed under `test_data/examples/` must be exactly what the generator writes.

use std::path::{Path, PathBuf};

use uniphys_examples::{EXAMPLE_NAMES, write_catalogue};

const REGENERATE: &str = "regenerate them from the workspace root with \
    `cargo run -p uniphys_examples --example write_catalogue -- test_data/examples` \
    (later also `cargo run -p uniphys_cli -- examples --out test_data/examples`) and commit them";

fn committed_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../test_data/examples")
}

/// A fresh scratch directory under the system temp dir, removed on drop.
struct ScratchDir(PathBuf);

impl ScratchDir {
    fn new() -> Self {
        let dir =
            std::env::temp_dir().join(format!("uniphys_examples_committed_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        Self(dir)
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn committed_example_glbs_match_the_generator() {
    let scratch = ScratchDir::new();
    let written = write_catalogue(&scratch.0).unwrap();
    assert_eq!(written.len(), EXAMPLE_NAMES.len());
    for path in written {
        let file_name = path.file_name().unwrap();
        let committed_path = committed_dir().join(file_name);
        let fresh = std::fs::read(&path).unwrap();
        let committed = std::fs::read(&committed_path).unwrap_or_else(|e| {
            panic!(
                "cannot read {}: {e}; {REGENERATE}",
                committed_path.display()
            )
        });
        assert!(
            committed == fresh,
            "{} differs from the generator output ({} vs {} bytes); {REGENERATE}",
            committed_path.display(),
            committed.len(),
            fresh.len()
        );
    }
}

#[test]
fn the_examples_readme_says_how_to_regenerate() {
    let readme = std::fs::read_to_string(committed_dir().join("README.md")).unwrap();
    assert!(readme.contains("write_catalogue"));
}
