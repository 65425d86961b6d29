//! `articulation-bench`: the articulated assets the project has (the example assets and, when
//! given, PyBullet's data URDFs with movable joints and real PartNet-Mobility objects with their
//! part labels hidden) with their joints stripped, run through
//! `uniphys_pipeline::run` (whatever grounder is on this build), scored with the paper's
//! kinematic metrics against their own joints, upright and with each asset randomly rotated;
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
    let poses = if args.upright_only || args.decompose {
        vec![Pose::Upright]
    } else {
        vec![Pose::Upright, Pose::Rotated { seed: args.seed }]
    };
    for pose in poses {
        let result = run_pose(&assets, pose, args, scratch.path());
        println!("{}", tables::pose_section(pose, &result));
        println!("{}", joint_tables::joint_sections(&result));
        all_skipped.extend(result.skipped);
    }
    println!("{}", tables::skipped_section(&all_skipped));
    println!("total wall time {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}
