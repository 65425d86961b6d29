//! `verify-bench`: the verifier judged on real articulated objects (issue 23). For every object
//! of a PartNet-Mobility folder set (default `../shared/data/partnet-mobility/`):
//! 1. its true joints go to the verifier as any grounder's would (swept, correctable): how many
//!    pass, how many a correction changes, by joint kind;
//! 2. each movable joint broken on purpose (axis turned 90 degrees, pivot moved to the opposite
//!    edge, direction reversed, prismatic made revolute and revolute made prismatic): how many
//!    the sweep catches, and how many the correction restores to the truth;
//! 3. the pivot candidates of each rotating joint: the nearest one's distance to the true axis
//!    line in the object's [0,2] frame.
//!
//! Markdown tables on stdout; `--json FILE` writes every joint's outcome.

mod breakage;
mod object;
#[path = "../object_dirs.rs"]
mod object_dirs;
mod tables;

use object_dirs::{folder_name, object_dirs};

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;

/// Arguments of `verify-bench`.
#[derive(Debug, Parser)]
#[command(
    name = "verify-bench",
    about = "The verifier on real articulated objects"
)]
struct Args {
    /// Folder of PartNet-Mobility objects (one sub-folder with a `mobility.urdf` each).
    #[arg(long, default_value = "../shared/data/partnet-mobility")]
    data: PathBuf,
    /// Only objects whose folder name contains one of these.
    #[arg(long, num_args = 1..)]
    only: Vec<String>,
    /// Skip the deliberate breakages (true joints and pivot candidates only).
    #[arg(long)]
    no_breakage: bool,
    /// Only these breakages (axis, pivot, reversed, p2r, r2p); all when none is given.
    #[arg(long, num_args = 1..)]
    breakage: Vec<String>,
    /// Write every joint's outcome as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
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

fn bench(args: &Args) -> anyhow::Result<()> {
    let start = Instant::now();
    let dirs = object_dirs(&args.data, &|name| {
        args.only.is_empty() || args.only.iter().any(|o| name.contains(o.as_str()))
    })?;
    anyhow::ensure!(!dirs.is_empty(), "no objects under {}", args.data.display());
    let mut results = Vec::new();
    for (i, dir) in dirs.iter().enumerate() {
        let name = folder_name(dir);
        eprint!("[{}/{}] {name} ... ", i + 1, dirs.len());
        let breakages: Vec<breakage::Breakage> = if args.no_breakage {
            Vec::new()
        } else {
            breakage::Breakage::ALL
                .into_iter()
                .filter(|b| args.breakage.is_empty() || args.breakage.iter().any(|k| k == b.key()))
                .collect()
        };
        let result = object::judge_object(dir, &breakages);
        match &result {
            Ok(r) => eprintln!(
                "{} joints, {} pass, {:.1} s",
                r.joints.len(),
                r.joints.iter().filter(|j| j.passed_unchanged()).count(),
                r.seconds
            ),
            Err(e) => eprintln!("skipped: {e:#}"),
        }
        results.push((name, result));
    }
    println!("{}", tables::report(&results));
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_vec_pretty(&tables::json(&results))?)?;
    }
    println!("total wall time {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}
