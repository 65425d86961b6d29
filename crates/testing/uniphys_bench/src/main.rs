//! `articulation-bench`: the articulated assets the project has (the example assets and, when
//! given, PyBullet's data URDFs with movable joints and real PartNet-Mobility objects with their
//! part labels hidden) with their joints stripped, run through
//! `uniphys_pipeline::run` (whatever grounder is on this build), scored with the paper's
//! kinematic metrics against their own joints, upright and in passes with each asset randomly
//! rotated (`--rotations`, 3 by default);
//! Markdown tables next to the paper's PartNet-Mobility rows.

mod assets;
mod bench_args;
mod categories;
mod decomposed_run;
mod joint_tables;
mod object_dirs;
mod partnet;
mod pose_run;
mod tables;

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;

use crate::bench_args::BenchArgs;
use crate::pose_run::{Pose, run_pose};

/// Seeds of successive rotated passes lie this far apart, so that no asset gets the same
/// rotation in two passes (assets take `seed + index`).
const ROTATION_SEED_STRIDE: u64 = 1000;

fn main() -> ExitCode {
    match bench(&BenchArgs::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

fn bench(args: &BenchArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let scratch = tempfile::tempdir()?;
    let (assets, skipped) = assets::collect(args, scratch.path())?;
    eprintln!(
        "{} articulated assets, {} skipped while collecting",
        assets.len(),
        skipped.len()
    );
    println!("# Articulation benchmark: joints stripped, built-in grounder, paper metrics\n");
    let mut all_skipped = skipped;
    let rotations = if args.upright_only || args.decompose {
        0
    } else {
        args.rotations
    };
    let poses = std::iter::once(Pose::Upright).chain((0..rotations).map(|k| Pose::Rotated {
        seed: args.seed.wrapping_add(ROTATION_SEED_STRIDE * k),
    }));
    let mut compared = Vec::new();
    for pose in poses {
        let result = run_pose(&assets, pose, args, scratch.path());
        println!("{}", tables::pose_section(pose, &result));
        println!("{}", joint_tables::joint_sections(&result));
        compared.push((pose, result.overall));
        all_skipped.extend(result.skipped);
    }
    if compared.len() > 1 {
        println!("{}", tables::poses_section(&compared));
    }
    println!("{}", tables::skipped_section(&all_skipped));
    println!("total wall time {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}
