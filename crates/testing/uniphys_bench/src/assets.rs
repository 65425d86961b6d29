//! The benchmark's assets: the example assets (written as GLB, ground truth from memory),
//! PyBullet's data URDFs with movable joints (ground truth from the URDF itself) and real
//! PartNet-Mobility objects with their part labels hidden (ground truth from the original URDF).

use std::path::{Path, PathBuf};

use anyhow::Context;
use uniphys_geometry::MeshAsset;
use uniphys_mesh_io::{IngestOptions, load_asset};

use crate::bench_args::BenchArgs;

/// Where an asset's ground-truth joints come from.
pub(crate) enum GroundTruth {
    /// An example asset in memory, in the frame its GLB is read into.
    Example(Box<MeshAsset>),
    /// The URDF that is also the input.
    Urdf(PathBuf),
}

/// One articulated asset.
pub(crate) struct BenchAsset {
    /// Example name or URDF path relative to the data folder.
    pub name: String,
    /// The input given to the pipeline.
    pub input: PathBuf,
    /// Its ground truth.
    pub ground_truth: GroundTruth,
    /// The group the asset is reported in.
    pub group: &'static str,
    /// Object category (PartNet-Mobility's `INDEX.tsv`), for per-category rows; empty if none.
    pub category: String,
}

/// An asset left out, and why.
pub(crate) struct Skipped {
    /// Asset name.
    pub name: String,
    /// Why (the ingest's or the pipeline's message, or the size filter).
    pub reason: String,
}

/// The examples and, if given, PyBullet's URDFs with movable joints that load and fit the size
/// limits; everything left out is listed.
pub(crate) fn collect(
    args: &BenchArgs,
    scratch: &Path,
) -> anyhow::Result<(Vec<BenchAsset>, Vec<Skipped>)> {
    let wanted = |name: &str| args.only.as_deref().is_none_or(|o| name.contains(o));
    let mut assets = Vec::new();
    let mut skipped = Vec::new();
    for example in uniphys_examples::catalogue() {
        if args.no_examples || !wanted(example.name) {
            continue;
        }
        let path = scratch.join(format!("{}.glb", example.name));
        let bytes = uniphys_examples::write_glb(&example.asset, uniphys_examples::GlbFrame::YUp)
            .with_context(|| format!("failed to write the example {}", example.name))?;
        std::fs::write(&path, bytes)
            .with_context(|| format!("failed to write {}", path.display()))?;
        assets.push(BenchAsset {
            name: example.name.to_owned(),
            input: path,
            ground_truth: GroundTruth::Example(Box::new(example.asset)),
            group: "example assets",
            category: String::new(),
        });
    }
    if let Some(root) = &args.pybullet_data {
        for path in urdfs_with_movable_joints(root)? {
            let name = path
                .strip_prefix(root)
                .unwrap_or(&path)
                .display()
                .to_string();
            if !wanted(&name) {
                continue;
            }
            match check_urdf(&path, args) {
                Ok(()) => assets.push(BenchAsset {
                    name,
                    input: path.clone(),
                    ground_truth: GroundTruth::Urdf(path),
                    group: "PyBullet URDFs",
                    category: String::new(),
                }),
                Err(reason) => skipped.push(Skipped { name, reason }),
            }
        }
    }
    if let Some(root) = &args.partnet {
        for copy in crate::partnet::hidden_copies(root, &scratch.join("partnet"), &wanted)? {
            assets.push(BenchAsset {
                name: copy.name,
                input: copy.input,
                ground_truth: GroundTruth::Urdf(copy.original),
                group: "PartNet-Mobility, labels hidden",
                category: copy.category,
            });
        }
    }
    Ok((assets, skipped))
}

/// Loads the URDF as ground truth would be loaded and applies the size filters.
fn check_urdf(path: &Path, args: &BenchArgs) -> Result<(), String> {
    let options = IngestOptions {
        max_triangles: args.max_triangles,
        ..IngestOptions::default()
    };
    let loaded = load_asset(path, &options).map_err(|e| e.to_string())?;
    let parts = loaded.asset.parts.len();
    if parts > args.max_parts {
        return Err(format!(
            "{parts} parts, more than --max-parts {}",
            args.max_parts
        ));
    }
    if !loaded.asset.joints.iter().any(|j| j.kind.is_movable()) {
        return Err("no movable joint between parts with geometry after ingest".to_owned());
    }
    Ok(())
}

/// `*.urdf` files under `root` (sorted) that declare a revolute, prismatic or continuous joint.
fn urdfs_with_movable_joints(root: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries =
            std::fs::read_dir(&dir).with_context(|| format!("failed to list {}", dir.display()))?;
        for entry in entries.filter_map(Result::ok) {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "urdf")
                && std::fs::read_to_string(&path).is_ok_and(|t| declares_movable_joint(&t))
            {
                found.push(path);
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Whether a `<joint ...>` tag has `type="revolute|prismatic|continuous"`.
fn declares_movable_joint(urdf: &str) -> bool {
    urdf.split("<joint").skip(1).any(|rest| {
        let tag: String = rest
            .split('>')
            .next()
            .unwrap_or("")
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect();
        ["revolute", "prismatic", "continuous"]
            .iter()
            .any(|t| tag.contains(&format!("type=\"{t}\"")))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn movable_joint_tags_are_found_and_fixed_ones_are_not() {
        assert!(declares_movable_joint(
            r#"<robot><joint name="a" type = "revolute"></joint>"#
        ));
        assert!(!declares_movable_joint(
            r#"<robot><joint name="a" type="fixed"/>"#
        ));
        assert!(!declares_movable_joint(r#"<robot><link name="revolute"/>"#));
    }
}
