//! `uniphys stage run <stage> <asset> --out <dir>`: one stage alone on a local file, no servers.
//! Stages that can run alone: `decompose`.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use uniphys_decompose::{
    DecomposeOptions, PerceptionOptions, ViewOptions, decompose_asset, generator_for, segmenter_for,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::ServiceStage;
use uniphys_vision::ClientConfig;

use crate::args::{StageRunArgs, metres_per_unit};

/// Stages `stage run` knows.
const RUNNABLE: [ServiceStage; 1] = [ServiceStage::Decompose];

pub(crate) fn run_stage(stage: &str, args: &StageRunArgs) -> anyhow::Result<ExitCode> {
    match ServiceStage::from_name(stage) {
        Some(ServiceStage::Decompose) => decompose(args),
        _ => anyhow::bail!(
            "stage {stage:?} cannot run alone; stages that can: {}",
            RUNNABLE.map(ServiceStage::name).join(", ")
        ),
    }
}

fn decompose(args: &StageRunArgs) -> anyhow::Result<ExitCode> {
    let ingest = IngestOptions {
        up_axis: args.up.up_axis(),
        metres_per_unit: metres_per_unit(&args.unit)?,
        max_triangles: args.max_triangles,
        ..IngestOptions::default()
    };
    let loaded = load_asset(&args.asset, &ingest)
        .with_context(|| format!("failed to read {}", args.asset.display()))?;
    let options = DecomposeOptions {
        perception: PerceptionOptions {
            views: ViewOptions {
                count: args.views,
                resolution_px: args.resolution_px,
            },
            threads: args.threads,
            ..PerceptionOptions::default()
        },
        seed: args.seed,
        ..DecomposeOptions::default()
    };
    let sam = args.sam_url.clone().map(ClientConfig::for_url);
    let partfield = args.partfield_url.clone().map(ClientConfig::for_url);
    let segmenter = segmenter_for(sam.as_ref()).context("the SAM-compatible service settings")?;
    let generator =
        generator_for(partfield.as_ref()).context("the PartField-compatible service settings")?;
    let (_, decomposition) = decompose_asset(
        &loaded.asset,
        segmenter.as_ref(),
        generator.as_ref(),
        &options,
    )?;
    let mesh = loaded.asset.merged();
    let files = decomposition.files(&mesh)?;
    write_all(&args.out, &files)?;
    let summary = &decomposition.summary;
    eprintln!(
        "{} faces -> {} parts ({} and {}; masks {}, K prior {}, matched K {}, refined {}, merged {} by {} ({} panels with a handle kept apart), refined again {}, small parts merged {}) in {:.2} s; wrote {} files to {}",
        summary.faces,
        summary.final_parts,
        summary.segmenter,
        summary.generator,
        summary.masks,
        summary.k_prior,
        summary.matched_k,
        summary.refined_parts,
        summary.merged_parts,
        summary.merge_strategy,
        summary.panels_kept_apart,
        summary.refined_again_parts,
        summary.small_parts_merged,
        summary.total_secs(),
        files.len(),
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn write_all(out: &Path, files: &[(String, Vec<u8>)]) -> anyhow::Result<()> {
    for (relative, bytes) in files {
        let path = out.join(relative);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("failed to create {}", dir.display()))?;
        }
        std::fs::write(&path, bytes)
            .with_context(|| format!("failed to write {}", path.display()))?;
    }
    Ok(())
}
