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
    eprintln!(
        "exported {} ({} files, {:?}) into {}",
        exported.record.name,
        chosen.len(),
        args.format,
        out.display()
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

fn write(out: &Path, artifact: &Artifact) -> anyhow::Result<()> {
    let path = out.join(&artifact.path);
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder)
            .with_context(|| format!("cannot create {}", folder.display()))?;
    }
    std::fs::write(&path, &artifact.bytes)
        .with_context(|| format!("cannot write {}", path.display()))
}
