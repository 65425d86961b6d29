//! `uniphys export`: an earlier result exported again from its own files
//! ([`uniphys_export::Exported`]), all of it or one simulator's model with the files it reads.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use uniphys_export::{Artifact, Exported, MESH_DIR};

use crate::args::{ExportArgs, ExportFormat};

pub(crate) fn export(args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let result = &args.result;
    if !result.join("record.json").is_file() {
        anyhow::bail!(
            "{} holds no record.json: give a folder `uniphys run` wrote",
            result.display()
        );
    }
    let read = |path: &str| std::fs::read(result.join(path)).ok();
    let exported = Exported::read(&read)
        .with_context(|| format!("cannot read the result in {}", result.display()))?;
    let output = uniphys_export::export(&exported.input()).context("export failed")?;
    let out = args.out.as_deref().unwrap_or(result);
    let chosen: Vec<&Artifact> = output
        .artifacts
        .iter()
        .filter(|a| wanted(args.format, &a.path))
        .collect();
    for artifact in &chosen {
        write(out, artifact)?;
    }
    let removed = if args.format == ExportFormat::All {
        remove_stale(out, &output.artifacts)?
    } else {
        0
    };
    eprintln!(
        "exported {} ({} files, {:?}) into {}{}",
        exported.record.name,
        chosen.len(),
        args.format,
        out.display(),
        if removed > 0 {
            format!("; removed {removed} files of an earlier export it no longer writes")
        } else {
            String::new()
        }
    );
    Ok(ExitCode::SUCCESS)
}

/// Whether `path` belongs to `format`: its model file, and the meshes and textures it reads.
fn wanted(format: ExportFormat, path: &str) -> bool {
    let in_meshes = path.starts_with(&format!("{MESH_DIR}/"));
    match format {
        ExportFormat::All => true,
        ExportFormat::Urdf => path == "model.urdf" || path == "model.srdf" || in_meshes,
        ExportFormat::Mjcf => path == "model.xml" || in_meshes,
        ExportFormat::Usd => path == "model.usda" || (in_meshes && path.ends_with(".png")),
    }
}

/// Folders every file of which an export writes: after a whole export (`--format all`), a file in
/// them that the export did not write is left over from an earlier one (a mesh split differently)
/// and is removed. A single format leaves them alone: the other models there, not rewritten, may
/// still read such a file.
const EXPORT_FOLDERS: [&str; 3] = [MESH_DIR, "parts", "annotations"];

/// Writes one file whole or not at all: its bytes go to a hidden file beside it, renamed over it.
fn write(out: &Path, artifact: &Artifact) -> anyhow::Result<()> {
    let path = out.join(&artifact.path);
    let folder = path.parent().unwrap_or(out);
    std::fs::create_dir_all(folder)
        .with_context(|| format!("cannot create {}", folder.display()))?;
    let name = path.file_name().map_or_else(
        || artifact.path.clone(),
        |n| n.to_string_lossy().into_owned(),
    );
    let partial = folder.join(format!(".{name}.partial"));
    std::fs::write(&partial, &artifact.bytes)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    std::fs::rename(&partial, &path)
        .with_context(|| format!("cannot move {} to {}", partial.display(), path.display()))
}

/// Removes the files in [`EXPORT_FOLDERS`] under `out` that are not among `written`; returns how
/// many.
fn remove_stale(out: &Path, written: &[Artifact]) -> anyhow::Result<usize> {
    let kept: std::collections::BTreeSet<&str> = written.iter().map(|a| a.path.as_str()).collect();
    let mut removed = 0;
    for folder in EXPORT_FOLDERS {
        let dir = out.join(folder);
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries {
            let entry = entry.with_context(|| format!("cannot list {}", dir.display()))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if !entry.path().is_file() || kept.contains(format!("{folder}/{name}").as_str()) {
                continue;
            }
            std::fs::remove_file(entry.path())
                .with_context(|| format!("cannot remove {}", entry.path().display()))?;
            removed += 1;
        }
    }
    Ok(removed)
}
