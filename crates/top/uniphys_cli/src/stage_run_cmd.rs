//! `uniphys stage run <stage> <asset> --out <dir>`: one stage alone on a local file, no servers.
//! Stages that can run alone: `decompose`.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use uniphys_decompose::candidates::PartFieldGenerator;
use uniphys_decompose::segment::SamSegmenter;
use uniphys_decompose::{
    BuiltinSegmenter, CandidateGenerator, DecomposeOptions, GeometricGenerator, PerceptionOptions,
    Segmenter, ViewOptions, decompose_asset,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_vision::{ClientConfig, PartFieldClient, SamClient};

use crate::args::{StageRunArgs, metres_per_unit};

/// Stages `stage run` knows.
const RUNNABLE: [&str; 1] = ["decompose"];

pub(crate) fn run_stage(stage: &str, args: &StageRunArgs) -> anyhow::Result<ExitCode> {
    match stage {
        "decompose" => decompose(args),
        other => anyhow::bail!(
            "stage {other:?} cannot run alone; stages that can: {}",
            RUNNABLE.join(", ")
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
    let segmenter: Box<dyn Segmenter> = match &args.sam_url {
        Some(url) => Box::new(SamSegmenter::new(
            SamClient::new(ClientConfig::for_url(url.clone()))
                .context("the SAM-compatible service settings")?,
        )),
        None => Box::new(BuiltinSegmenter::default()),
    };
    let generator: Box<dyn CandidateGenerator> = match &args.partfield_url {
        Some(url) => Box::new(PartFieldGenerator::new(
            PartFieldClient::new(ClientConfig::for_url(url.clone()))
                .context("the PartField-compatible service settings")?,
        )),
        None => Box::new(GeometricGenerator::default()),
    };
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
        "{} faces -> {} parts ({} and {}; masks {}, K prior {}, matched K {}, refined {}, merged {} by {}, refined again {}, small parts merged {}) in {:.2} s; wrote {} files to {}",
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
