//! `decompose-bench`: multi-part assets (the example assets and, when given, PyBullet's data
//! URDFs with two or more parts) merged into one mesh, decomposed by the built-in providers, and
//! scored against their known parts (part-count error, face-area-weighted IoU after Hungarian
//! matching), with the time per asset; then the stage on a ~100k-triangle asset with 8 views at
//! 512 x 512 on one thread, total and per step. With `--partnet`, real objects instead: see
//! [`real`].

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::Parser;
use uniphys_decompose::{
    BuiltinSegmenter, DecomposeOptions, GeometricGenerator, PerceptionOptions, ViewOptions,
    cluster_faces, decompose_asset, score_parts,
};
use uniphys_geometry::{DVec3, MeshAsset, MeshPart, TriMesh};
use uniphys_mesh_io::{IngestOptions, load_asset};

#[path = "../categories.rs"]
mod categories;
#[path = "../object_dirs.rs"]
mod object_dirs;
mod partnet;
mod real;
mod steps;

/// Decompose multi-part assets merged into one mesh and score the parts found.
#[derive(Debug, Parser)]
#[command(name = "decompose-bench", about)]
struct Args {
    /// PyBullet's data folder; its URDFs with 2 or more parts join the example assets.
    #[arg(long)]
    pybullet_data: Option<PathBuf>,
    /// Skip assets with more triangles than this.
    #[arg(long, default_value_t = 30_000)]
    max_triangles: usize,
    /// Skip assets with more parts than this.
    #[arg(long, default_value_t = 30)]
    max_parts: usize,
    /// Views per asset.
    #[arg(long, default_value_t = 8)]
    views: usize,
    /// Side of every view, pixels.
    #[arg(long, default_value_t = 512)]
    resolution_px: u32,
    /// Only assets whose name contains this text.
    #[arg(long)]
    only: Option<String>,
    /// A PartNet-Mobility folder: decompose its real objects instead of the examples and URDFs.
    #[arg(long)]
    partnet: Option<PathBuf>,
    /// With `--partnet`: write each object's merged mesh, true parts and the labels after every
    /// step of the stage to `<dir>/<object>.json`, for looking into where parts are lost.
    #[arg(long)]
    dump_steps: Option<PathBuf>,
    /// Triangles of the performance asset (a subdivided example cabinet); 0 skips it.
    #[arg(long, default_value_t = 100_000)]
    perf_triangles: usize,
}

fn main() -> ExitCode {
    match bench(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

/// An asset left out (name, reason).
type Skipped = (String, String);

/// One benchmark asset: its parts as given (the truth) and where it came from.
struct Case {
    name: String,
    asset: MeshAsset,
}

fn bench(args: &Args) -> anyhow::Result<()> {
    let start = Instant::now();
    if let Some(root) = &args.partnet {
        let wanted = |name: &str| args.only.as_deref().is_none_or(|o| name.contains(o));
        let (cases, failed) = partnet::real_cases(root, &wanted)?;
        let options = DecomposeOptions {
            keep_step_labels: true,
            ..options_for(args)
        };
        real::bench_real(&cases, &|case| {
            let (_, decomposition) = decompose_asset(
                &case.asset,
                &BuiltinSegmenter::default(),
                &GeometricGenerator::default(),
                &options,
            )?;
            if let Some(dir) = &args.dump_steps {
                partnet::dump_steps(dir, case, &decomposition)?;
            }
            Ok(decomposition)
        })?;
        for (name, reason) in &failed {
            println!("- FAILED to load {name}: {reason}");
        }
        println!("\ntotal wall time {:.1} s", start.elapsed().as_secs_f64());
        return Ok(());
    }
    let (cases, skipped) = collect(args)?;
    let options = options_for(args);
    println!(
        "# Decomposition benchmark: assets merged into one mesh, built-in segmenter and generator, {} views at {} px\n",
        args.views, args.resolution_px
    );
    println!("| asset | faces | true parts | found parts | abs count error | area IoU | time s |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    let mut rows: Vec<(usize, f64, f64)> = Vec::new();
    let mut failed = Vec::new();
    for case in &cases {
        let (single, truth) = merged_with_truth(&case.asset);
        let clock = Instant::now();
        let result = decompose_asset(
            &single,
            &BuiltinSegmenter::default(),
            &GeometricGenerator::default(),
            &options,
        );
        let secs = clock.elapsed().as_secs_f64();
        let decomposition = match result {
            Ok((_, d)) => d,
            Err(error) => {
                failed.push((case.name.clone(), error.to_string()));
                continue;
            }
        };
        let mesh = single.merged();
        let areas: Vec<f64> = (0..mesh.triangle_count())
            .map(|f| mesh.face_area(f))
            .collect();
        let score = score_parts(&decomposition.face_part, &truth, &areas)?;
        println!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.2} |",
            case.name,
            mesh.triangle_count(),
            score.true_parts,
            score.found_parts,
            score.count_error,
            score.area_iou,
            secs
        );
        rows.push((score.count_error, score.area_iou, secs));
    }
    if !rows.is_empty() {
        let n = rows.len() as f64;
        println!(
            "| **mean of {}** | | | | {:.2} | {:.3} | {:.2} |",
            rows.len(),
            rows.iter().map(|r| r.0 as f64).sum::<f64>() / n,
            rows.iter().map(|r| r.1).sum::<f64>() / n,
            rows.iter().map(|r| r.2).sum::<f64>() / n
        );
        let exact = rows.iter().filter(|r| r.0 == 0).count();
        println!("\nexact part count on {exact} of {} assets", rows.len());
    }
    let single = skipped.iter().filter(|(_, r)| r == "1 parts").count();
    println!("\n{single} URDFs with a single part left out");
    for (name, reason) in skipped.iter().filter(|(_, r)| r != "1 parts") {
        println!("- skipped {name}: {reason}");
    }
    for (name, reason) in &failed {
        println!("- FAILED {name}: {reason}");
    }
    if args.perf_triangles > 0 {
        performance(args)?;
    }
    println!("\ntotal wall time {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

/// The stage's options with the views of `args`, one thread.
fn options_for(args: &Args) -> DecomposeOptions {
    DecomposeOptions {
        perception: PerceptionOptions {
            views: ViewOptions {
                count: args.views,
                resolution_px: args.resolution_px,
            },
            threads: 1,
            ..PerceptionOptions::default()
        },
        ..DecomposeOptions::default()
    }
}

/// The asset as one part (faces in part order) and the true part of every face.
fn merged_with_truth(asset: &MeshAsset) -> (MeshAsset, Vec<u32>) {
    let truth: Vec<u32> = asset
        .parts
        .iter()
        .enumerate()
        .flat_map(|(i, p)| {
            std::iter::repeat_n(
                u32::try_from(i).unwrap_or(u32::MAX),
                p.mesh.triangle_count(),
            )
        })
        .collect();
    let single = MeshAsset {
        parts: vec![MeshPart {
            name: "merged".into(),
            mesh: asset.merged(),
        }],
        materials: asset.materials.clone(),
        textures: asset.textures.clone(),
        joints: Vec::new(),
    };
    (single, truth)
}

/// The examples and PyBullet's URDFs with 2..=max_parts parts and at most max_triangles.
fn collect(args: &Args) -> anyhow::Result<(Vec<Case>, Vec<Skipped>)> {
    let wanted = |name: &str| args.only.as_deref().is_none_or(|o| name.contains(o));
    let mut cases = Vec::new();
    let mut skipped = Vec::new();
    for example in uniphys_examples::catalogue() {
        if wanted(example.name) {
            cases.push(Case {
                name: example.name.to_owned(),
                asset: example.asset,
            });
        }
    }
    let Some(root) = &args.pybullet_data else {
        return Ok((cases, skipped));
    };
    let options = IngestOptions {
        max_triangles: args.max_triangles,
        ..IngestOptions::default()
    };
    for path in urdfs(root)? {
        let name = path
            .strip_prefix(root)
            .unwrap_or(&path)
            .display()
            .to_string();
        if !wanted(&name) {
            continue;
        }
        match load_asset(&path, &options) {
            Ok(loaded) => {
                let parts = loaded.asset.parts.len();
                if parts < 2 || parts > args.max_parts {
                    skipped.push((name, format!("{parts} parts")));
                } else {
                    cases.push(Case {
                        name,
                        asset: loaded.asset,
                    });
                }
            }
            Err(error) => skipped.push((name, error.to_string())),
        }
    }
    Ok((cases, skipped))
}

/// `*.urdf` files under `root`, sorted.
fn urdfs(root: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries =
            std::fs::read_dir(&dir).with_context(|| format!("failed to list {}", dir.display()))?;
        for entry in entries.filter_map(Result::ok) {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "urdf") {
                found.push(path);
            }
        }
    }
    found.sort();
    Ok(found)
}

/// The whole stage on the cabinet example subdivided to about `perf_triangles` triangles,
/// 8 views at 512 x 512, one thread: total and per step.
fn performance(args: &Args) -> anyhow::Result<()> {
    let example = uniphys_examples::example("cabinet").context("the cabinet example is missing")?;
    let mut asset = example.asset;
    // One part at a time (smallest first), so the count lands near the target.
    while asset.triangle_count() < args.perf_triangles {
        let Some(smallest) =
            (0..asset.parts.len()).min_by_key(|&i| (asset.parts[i].mesh.triangle_count(), i))
        else {
            break;
        };
        asset.parts[smallest].mesh = subdivided(&asset.parts[smallest].mesh);
    }
    let (single, truth) = merged_with_truth(&asset);
    let options = DecomposeOptions {
        perception: PerceptionOptions {
            views: ViewOptions {
                count: 8,
                resolution_px: 512,
            },
            threads: 1,
            ..PerceptionOptions::default()
        },
        ..DecomposeOptions::default()
    };
    let clock = Instant::now();
    let (_, decomposition) = decompose_asset(
        &single,
        &BuiltinSegmenter::default(),
        &GeometricGenerator::default(),
        &options,
    )?;
    let wall = clock.elapsed().as_secs_f64();
    let mesh = single.merged();
    let areas: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    let score = score_parts(&decomposition.face_part, &truth, &areas)?;
    println!(
        "\n## Performance: cabinet subdivided to {} triangles, 8 views at 512 x 512, one thread\n",
        mesh.triangle_count()
    );
    println!("| step | s |");
    println!("|---|---:|");
    for timing in &decomposition.summary.timings {
        println!("| {} | {:.3} |", timing.step, timing.secs);
    }
    println!("| **stage total (wall, incl. colours)** | **{wall:.3}** |");
    // The per-face path (PartField-compatible features): Ward over every face, K = 1..=20.
    let features: Vec<f32> = (0..mesh.triangle_count())
        .flat_map(|f| {
            let [a, b, c] = mesh.corners(f);
            let centre = (a + b + c) / 3.0;
            let normal = mesh.face_normal(f);
            [centre.x, centre.y, centre.z, normal.x, normal.y, normal.z].map(|x| x as f32)
        })
        .collect();
    let clock = Instant::now();
    let per_face = cluster_faces(&mesh, &features, 6, 1..=20)?;
    println!(
        "| cluster_faces alone, per-face rows (6 dims), K = 1..=20 ({} candidates) | {:.3} |",
        per_face.len(),
        clock.elapsed().as_secs_f64()
    );
    let summary = &decomposition.summary;
    println!(
        "\nparts found {} of {} true, area IoU {:.3}; masks {}, informative views {}, K prior {}, matched K {} (by {}), refined {}, merged {} ({}), refined again {}, small parts merged {}",
        score.found_parts,
        score.true_parts,
        score.area_iou,
        summary.masks,
        summary.informative_views,
        summary.k_prior,
        summary.matched_k,
        summary.selected_by,
        summary.refined_parts,
        summary.merged_parts,
        summary.merge_strategy,
        summary.refined_again_parts,
        summary.small_parts_merged
    );
    Ok(())
}

/// Every triangle cut into four at its edge midpoints (shared edges get one midpoint vertex).
fn subdivided(mesh: &TriMesh) -> TriMesh {
    let mut positions = mesh.positions.clone();
    let mut midpoint: std::collections::BTreeMap<(u32, u32), u32> =
        std::collections::BTreeMap::new();
    let mut mid = |a: u32, b: u32, positions: &mut Vec<DVec3>| -> u32 {
        let key = (a.min(b), a.max(b));
        *midpoint.entry(key).or_insert_with(|| {
            positions.push((positions[a as usize] + positions[b as usize]) * 0.5);
            u32::try_from(positions.len() - 1).unwrap_or(u32::MAX)
        })
    };
    let mut triangles = Vec::with_capacity(mesh.triangles.len() * 4);
    let mut materials = Vec::with_capacity(mesh.triangles.len() * 4);
    for (f, &[a, b, c]) in mesh.triangles.iter().enumerate() {
        let (ab, bc, ca) = (
            mid(a, b, &mut positions),
            mid(b, c, &mut positions),
            mid(c, a, &mut positions),
        );
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        if let Some(m) = mesh.face_materials.as_ref().and_then(|m| m.get(f)) {
            materials.extend([*m; 4]);
        }
    }
    TriMesh {
        positions,
        triangles,
        uvs: None,
        vertex_colors: None,
        face_materials: mesh.face_materials.as_ref().map(|_| materials),
    }
}
