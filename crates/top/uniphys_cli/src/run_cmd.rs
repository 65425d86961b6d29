use std::process::ExitCode;

use anyhow::Context;
use uniphys_decompose::DecomposeOptions;
use uniphys_mesh_io::{AssetRotation, IngestOptions};
use uniphys_pipeline::{LearnedOptions, RunOptions, run as run_pipeline};
use uniphys_storage::ArtifactStore;
use uniphys_uniphysgen::ClientConfig;

use crate::args::{RunArgs, metres_per_unit, unit_is_auto};
use crate::out_dir::{check_out_dir, clear_out_dir};
use crate::progress::StderrProgress;
use crate::report_notes::with_notes;

pub(crate) fn run(args: &RunArgs) -> anyhow::Result<ExitCode> {
    check_out_dir(
        &args.out,
        &uniphys_pipeline::asset_name(&args.asset),
        args.force,
    )?;
    let mut options = RunOptions {
        ingest: IngestOptions {
            up_axis: args.up.up_axis(),
            metres_per_unit: metres_per_unit(&args.unit)?,
            max_triangles: args.max_triangles,
            ignore_joints: args.ignore_joints,
            rotation: args.rotate_seed.map(AssetRotation::from_seed),
            ..IngestOptions::default()
        },
        voxel_resolution: args.voxel_resolution,
        unit_auto: unit_is_auto(&args.unit),
        ..RunOptions::default()
    };
    options.convex.max_hulls = args.max_hulls;
    options.decompose = args.decompose.then(DecomposeOptions::default);
    options.learned = args.uniphysgen_url.as_ref().map(|url| LearnedOptions {
        client: ClientConfig {
            base_url: url.clone(),
            ..ClientConfig::default()
        },
        slots: args.uniphysgen_slots,
        ..LearnedOptions::default()
    });
    options.lvlm = args.lvlm.options(None)?;
    let progress = StderrProgress::new(options.learned.is_some());
    let mut output = run_pipeline(&args.asset, &options, &progress)?;
    let ingest_notes = options.ingest.transform_notes();
    if let Some(report) = output
        .artifacts
        .iter_mut()
        .find(|a| a.path == "report.json")
    {
        report.bytes = with_notes(&report.bytes, &ingest_notes)?;
    }

    clear_out_dir(&args.out)?;
    let store = ArtifactStore::local(&args.out)?;
    let runtime = tokio::runtime::Builder::new_current_thread()
        .build()
        .context("failed to start the IO runtime")?;
    runtime.block_on(async {
        for artifact in &output.artifacts {
            store.put(&artifact.path, artifact.bytes.clone()).await?;
        }
        anyhow::Ok(())
    })?;

    let record = &output.record;
    let movable: Vec<String> = record
        .joints
        .iter()
        .filter(|j| j.kind.is_movable())
        .map(|j| format!("{} ({:?})", j.name, j.kind).to_lowercase())
        .collect();
    let failures: Vec<String> = output
        .report
        .failures()
        .map(|c| format!("{} {}: {}", c.subject, c.check, c.message))
        .collect();
    let total_ms: f64 = output
        .timings
        .iter()
        .map(|(_, d)| d.as_secs_f64() * 1e3)
        .sum();
    if args.json {
        let summary = serde_json::json!({
            "asset": record.name,
            "out": args.out,
            "parts": record.parts.len(),
            "movable_joints": movable,
            "mass_kg": record.object.mass_kg.value,
            "category": record.object.category.value,
            "passed": failures.is_empty(),
            "failures": failures,
            "timings_ms": output.timings.iter().map(|(s, d)| (s.name(), d.as_secs_f64() * 1e3)).collect::<std::collections::BTreeMap<_, _>>(),
        });
        println!("{summary}");
    } else {
        println!(
            "{}: {} parts, {} movable joints [{}]",
            record.name,
            record.parts.len(),
            movable.len(),
            movable.join(", ")
        );
        println!(
            "object: {} ({}), {:.3} kg, {:.3} x {:.3} x {:.3} m",
            record.object.name.value,
            record.object.category.value,
            record.object.mass_kg.value,
            record.object.dimensions_m.value[0],
            record.object.dimensions_m.value[1],
            record.object.dimensions_m.value[2]
        );
        println!(
            "wrote {} files to {} in {total_ms:.0} ms (model.urdf, model.srdf, model.xml, model.usda, report.json, annotations/)",
            output.artifacts.len(),
            args.out.display()
        );
        if failures.is_empty() {
            println!("all checks passed");
        } else {
            println!("{} checks failed (see report.json):", failures.len());
            for f in &failures {
                println!("  {f}");
            }
        }
    }
    Ok(if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
