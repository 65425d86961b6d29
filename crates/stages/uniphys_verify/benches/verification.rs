//! Verification time per joint of the example assets:
//! `cargo bench -p uniphys_verify --bench verification -- [--emit DIR]`.
//!
//! Prints one row per movable example joint: the full sweep (`SweepParams::default()`: 200
//! steps, 1500 samples per part), the time per step, and the time `correct_joint` takes to fix the
//! joint with its axis negated; medians of a few runs, wall-clock, one thread.
//!
//! With `--emit DIR` it also writes the inputs of `bench/verification.py` (part meshes as OBJ,
//! the point sets of each contact search at rest as `.npy`) and our own times of the volume and
//! contact computations on them (`DIR/ours.json`), so that the script times trimesh and scipy on
//! exactly the same data (see `verification/emit.rs`).

#[path = "verification/emit.rs"]
mod emit;
#[path = "verification/fixture.rs"]
mod fixture;

use std::path::PathBuf;
use std::time::Instant;

use uniphys_types::Joint;
use uniphys_verify::{SweepParams, correct_joint, moving_group, sweep};

use fixture::Fixture;

/// Runs of each full sweep.
const SWEEP_RUNS: usize = 3;
/// Runs of each correction (a correction is a few sweeps).
const CORRECT_RUNS: usize = 3;

/// Median wall-clock time of `runs` calls of `f`, milliseconds, and the last result.
pub(crate) fn median_ms<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut times = Vec::with_capacity(runs);
    let mut last = None;
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        last = Some(f());
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], last.expect("at least one run"))
}

/// The `--emit DIR` argument, if any (cargo bench also passes `--bench`, ignored).
fn emit_dir() -> Option<PathBuf> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == "--emit")
        .map(|i| PathBuf::from(args.get(i + 1).expect("--emit needs a directory")))
}

/// `joint` with its axis negated: the motion goes the wrong way.
fn reversed(joint: &Joint) -> Joint {
    let mut j = joint.clone();
    j.axis_in_object = j.axis_in_object.map(|a| -a);
    j
}

fn verdict(reasons: &[String]) -> &'static str {
    if reasons.is_empty() { "pass" } else { "fail" }
}

fn main() {
    let params = SweepParams::default();
    let emit = emit_dir();
    let fixtures: Vec<Fixture> = uniphys_examples::EXAMPLE_NAMES
        .iter()
        .map(|name| Fixture::new(name))
        .collect();
    println!(
        "# articulation sweep per joint: {} steps, {} samples per part; median of {SWEEP_RUNS} \
         sweeps, {CORRECT_RUNS} corrections (ms)\n",
        params.steps,
        fixture::SAMPLES_PER_PART
    );
    println!(
        "| asset | joint | kind | parts moving | hulls | sweep ms | us/step | verdict | \
         axis negated | correct ms | change |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for f in &fixtures {
        for joint in f.joints.iter().filter(|j| j.kind.is_movable()) {
            let moving = moving_group(&f.joints, joint.child);
            let (sweep_ms, metrics) = median_ms(SWEEP_RUNS, || {
                sweep(&f.scene, joint, &moving, &params).expect("sweep runs")
            });
            let wrong = reversed(joint);
            let wrong_reasons = sweep(&f.scene, &wrong, &moving, &params)
                .expect("sweep runs")
                .failures(&params);
            let (correct_ms, fix) = median_ms(CORRECT_RUNS, || {
                correct_joint(&f.scene, &wrong, &moving, &params).expect("correction runs")
            });
            println!(
                "| {} | {} | {:?} | {} | {} | {sweep_ms:.1} | {:.0} | {} | {} | {correct_ms:.1} | {} |",
                f.name,
                joint.name,
                joint.kind,
                moving.len(),
                f.hull_count,
                sweep_ms * 1e3 / params.steps as f64,
                verdict(&metrics.failures(&params)),
                verdict(&wrong_reasons),
                fix.map_or_else(|| "none passed".to_owned(), |c| c.change),
            );
        }
    }
    if let Some(dir) = emit {
        emit::write(&dir, &fixtures, &params).expect("emit the comparison inputs");
        println!(
            "\nwrote meshes, point sets and our timings to {}",
            dir.display()
        );
    }
}
