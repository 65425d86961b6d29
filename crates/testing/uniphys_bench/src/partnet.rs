//! PartNet-Mobility objects as the issue's new user sees them: a copy of each object without
//! `semantics.txt`, `mobility_v2.json` and `meta.json`, and without the `name` attributes of
//! `<visual>` and `<collision>` (they carry the part labels), so the grounder sees only geometry
//! and links called `link_0`, `link_1`, ... The original URDF is the ground truth; the category
//! (from the folder's `INDEX.tsv`) is read for the tables only.

use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::categories::read_categories;
use crate::object_dirs::{folder_name, object_dirs};

/// One object copied with its labels hidden.
pub(crate) struct HiddenCopy {
    /// Folder name.
    pub name: String,
    /// The copy's URDF (the pipeline's input).
    pub input: PathBuf,
    /// The original URDF (the ground truth).
    pub original: PathBuf,
    /// Category from `INDEX.tsv`, `?` if absent.
    pub category: String,
}

/// Copies every object folder of `root` (those with a `mobility.urdf`) into `scratch` with its
/// labels hidden; `wanted` filters by folder name.
pub(crate) fn hidden_copies(
    root: &Path,
    scratch: &Path,
    wanted: &dyn Fn(&str) -> bool,
) -> anyhow::Result<Vec<HiddenCopy>> {
    let categories = read_categories(root);
    let mut out = Vec::new();
    for dir in object_dirs(root, wanted)? {
        let name = folder_name(&dir);
        let copy = scratch.join(&name);
        std::fs::create_dir_all(&copy)
            .with_context(|| format!("failed to create {}", copy.display()))?;
        let original = dir.join("mobility.urdf");
        let text = std::fs::read_to_string(&original)
            .with_context(|| format!("failed to read {}", original.display()))?;
        let input = copy.join("mobility.urdf");
        std::fs::write(&input, strip_part_labels(&text))
            .with_context(|| format!("failed to write {}", input.display()))?;
        let meshes = dir.join("textured_objs");
        if meshes.is_dir() {
            link_tree(&meshes, &copy.join("textured_objs"))?;
        }
        out.push(HiddenCopy {
            category: categories
                .get(&name)
                .cloned()
                .unwrap_or_else(|| "?".to_owned()),
            name,
            input,
            original,
        });
    }
    Ok(out)
}

/// Mirrors the files under `from` into `to`, hard-linked where the file system allows (the
/// ingest refuses references that leave the asset's folder, so a symbolic link would not do),
/// copied otherwise.
fn link_tree(from: &Path, to: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(to).with_context(|| format!("failed to create {}", to.display()))?;
    for entry in std::fs::read_dir(from)
        .with_context(|| format!("failed to list {}", from.display()))?
        .filter_map(Result::ok)
    {
        let source = entry.path();
        let target = to.join(entry.file_name());
        if source.is_dir() {
            link_tree(&source, &target)?;
        } else if !target.exists() && std::fs::hard_link(&source, &target).is_err() {
            std::fs::copy(&source, &target)
                .with_context(|| format!("failed to copy {}", source.display()))?;
        }
    }
    Ok(())
}

/// The URDF text with the `name="..."` attribute removed from every `<visual ...>` and
/// `<collision ...>` opening tag.
fn strip_part_labels(urdf: &str) -> String {
    let mut out = String::with_capacity(urdf.len());
    let mut rest = urdf;
    while let Some(at) = rest.find('<') {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        let end = rest.find('>').map_or(rest.len(), |e| e + 1);
        let tag = &rest[..end];
        if tag.starts_with("<visual") || tag.starts_with("<collision") {
            out.push_str(&without_name_attribute(tag));
        } else {
            out.push_str(tag);
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

fn without_name_attribute(tag: &str) -> String {
    let Some(start) = tag.find(" name=") else {
        return tag.to_owned();
    };
    let value = &tag[start + " name=".len()..];
    let Some(quote) = value.chars().next().filter(|q| *q == '"' || *q == '\'') else {
        return tag.to_owned();
    };
    let Some(close) = value[1..].find(quote) else {
        return tag.to_owned();
    };
    format!("{}{}", &tag[..start], &value[close + 2..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_of_visuals_and_collisions_are_removed_and_link_names_kept() {
        let urdf = r#"<link name="link_0"><visual name="lid-11"><origin/></visual><collision name='x' ><geometry/></collision></link>"#;
        let out = strip_part_labels(urdf);
        assert_eq!(
            out,
            r#"<link name="link_0"><visual><origin/></visual><collision ><geometry/></collision></link>"#
        );
    }
}
