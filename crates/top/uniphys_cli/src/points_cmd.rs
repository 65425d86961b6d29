//! `uniphys points`: the UniPhysGen point clouds of an asset in the reference's npz layout, and
//! the frame that maps the model's answers back.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use serde_json::json;
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_uniphysgen::{PointOptions, model_inputs, prepare_points, write_npzs};

use crate::args::PointsArgs;

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// Writes the UniPhysGen model inputs of the asset at `asset` into `out` (`npzs/model.npz`,
/// `npzs/<part index>.npz`, `coordinate_frame.json`) with the default sampling; returns how
/// many npz files were written.
pub(crate) fn write_model_inputs(asset: &Path, out: &Path) -> anyhow::Result<usize> {
    let mut loaded = load_asset(asset, &IngestOptions::default())?;
    loaded.asset.rest_on_ground();
    let prepared = prepare_points(&loaded.asset, &PointOptions::default())?;
    let inputs = model_inputs(&prepared, uniphys_uniphysgen::DEFAULT_NUM_BINS)?;
    let written = write_npzs(&prepared, &out.join("npzs"))?;
    let frame_path = out.join("coordinate_frame.json");
    std::fs::write(
        &frame_path,
        serde_json::to_string_pretty(&inputs.frame.to_json())?,
    )
    .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", frame_path.display()))?;
    Ok(written.len())
}

pub(crate) fn points(args: &PointsArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    let mut loaded = load_asset(&args.asset, &IngestOptions::default())?;
    // The object frame of `uniphys run`: the coordinate frame maps back to the record's frame.
    loaded.asset.rest_on_ground();
    let load_ms = ms(start);

    let start = Instant::now();
    let options = PointOptions {
        object_points: args.object_points,
        min_part_points: args.min_part_points,
        seed: args.seed,
    };
    let prepared = prepare_points(&loaded.asset, &options)?;
    let sample_ms = ms(start);

    let start = Instant::now();
    let inputs = model_inputs(&prepared, args.num_bins)?;
    let frame_ms = ms(start);

    let start = Instant::now();
    let written = write_npzs(&prepared, &args.out.join("npzs"))?;
    let frame_path = args.out.join("coordinate_frame.json");
    let frame_json = serde_json::to_string_pretty(&inputs.frame.to_json())?;
    std::fs::write(&frame_path, frame_json)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", frame_path.display()))?;
    let write_ms = ms(start);

    // One machine-readable line for the benchmark (bench/uniphysgen_points.py).
    eprintln!(
        "uniphys points: timing_ms sample={sample_ms:.1} frame={frame_ms:.1} write={write_ms:.1} load={load_ms:.1}"
    );
    let files: Vec<&Path> = written.iter().map(|p| p.as_path()).collect();
    println!(
        "{}",
        json!({
            "asset": args.asset,
            "object_points": prepared.object.len(),
            "parts": prepared.parts.iter().map(|(id, c)| json!({"id": id, "points": c.len()})).collect::<Vec<_>>(),
            "object_voxels": inputs.object.len(),
            "num_bins": inputs.num_bins,
            "files": files,
            "coordinate_frame": frame_path,
        })
    );
    Ok(ExitCode::SUCCESS)
}
