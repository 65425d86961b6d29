//! `assets-bench`: real objects in, plausible assets out (issue 17). Every PartNet-Mobility
//! folder of a set (default `../shared/data/partnet-mobility/`) goes through the pipeline as
//! shipped (texture lines and all, `--unit auto`, its declared joints), and the bench prints:
//! 1. the outcome of each run as `uniphys run` would exit (0, 1 with the failed checks, refused);
//! 2. per category (from the folder's `meta.json`), the estimated largest side and mass next to
//!    the kind's typical ones (`uniphys_types::CATEGORY_PRIORS`), and the share of objects
//!    within a factor of 2 of the typical mass, with the misses listed;
//! 3. time per object.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[path = "../object_dirs.rs"]
mod object_dirs;

use clap::Parser;
use object_dirs::{folder_name, object_dirs};
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::CategoryPrior;

/// Arguments of `assets-bench`.
#[derive(Debug, Parser)]
#[command(
    name = "assets-bench",
    about = "Real objects through the pipeline: outcomes, sizes and masses"
)]
struct Args {
    /// Folder of PartNet-Mobility objects (one sub-folder with a `mobility.urdf` each).
    #[arg(long, default_value = "../shared/data/partnet-mobility")]
    data: PathBuf,
    /// Only objects whose folder name contains one of these.
    #[arg(long, num_args = 1..)]
    only: Vec<String>,
}

/// The factor within which an estimated mass counts as matching the typical one.
const MATCH_FACTOR: f64 = 2.0;

/// One object's run.
struct Outcome {
    object: String,
    category: String,
    /// `0`, `1` or `refused`, as `uniphys run` would end.
    exit: String,
    /// Failed checks (exit 1) or the error (refused).
    reasons: Vec<String>,
    largest_side_m: f64,
    mass_kg: f64,
    secs: f64,
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
    let dirs = object_dirs(&args.data, &|name| {
        args.only.is_empty() || args.only.iter().any(|o| name.contains(o.as_str()))
    })?;
    anyhow::ensure!(
        !dirs.is_empty(),
        "no folder with a mobility.urdf under {}",
        args.data.display()
    );
    let options = RunOptions::default();
    let mut outcomes = Vec::with_capacity(dirs.len());
    for (i, dir) in dirs.iter().enumerate() {
        let outcome = run_one(dir, &options);
        eprintln!(
            "[{}/{}] {} ({}): exit {} in {:.1} s",
            i + 1,
            dirs.len(),
            outcome.object,
            outcome.category,
            outcome.exit,
            outcome.secs
        );
        outcomes.push(outcome);
    }
    print_outcomes(&outcomes);
    print_categories(&outcomes);
    Ok(())
}

fn run_one(dir: &Path, options: &RunOptions) -> Outcome {
    let object = folder_name(dir);
    let category = meta_category(dir).unwrap_or_else(|| "unknown".to_owned());
    let start = Instant::now();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run(dir, options, &NoProgress)
    }));
    let secs = start.elapsed().as_secs_f64();
    let mut outcome = Outcome {
        object,
        category,
        exit: "refused".to_owned(),
        reasons: Vec::new(),
        largest_side_m: f64::NAN,
        mass_kg: f64::NAN,
        secs,
    };
    match result {
        Err(_) => outcome.reasons.push("panicked".to_owned()),
        Ok(Err(error)) => outcome.reasons.push(error.to_string()),
        Ok(Ok(output)) => {
            let failures: Vec<String> = output
                .report
                .failures()
                .map(|c| format!("{} {}: {}", c.subject, c.check, c.message))
                .collect();
            outcome.exit = if failures.is_empty() { "0" } else { "1" }.to_owned();
            outcome.reasons = failures;
            let object = &output.record.object;
            outcome.largest_side_m = object
                .dimensions_m
                .value
                .iter()
                .copied()
                .fold(0.0, f64::max);
            outcome.mass_kg = object.mass_kg.value;
        }
    }
    outcome
}

/// The `model_cat` of the folder's `meta.json`: the category the bench judges against.
fn meta_category(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join("meta.json")).ok()?;
    let value: serde_json::Value = serde_json::from_str(&text).ok()?;
    value.get("model_cat")?.as_str().map(str::to_owned)
}

fn print_outcomes(outcomes: &[Outcome]) {
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for o in outcomes {
        *counts.entry(o.exit.as_str()).or_default() += 1;
    }
    println!(
        "## Outcomes of `uniphys run` on {} real objects\n",
        outcomes.len()
    );
    println!("| exit | objects |\n|---|---|");
    for (exit, n) in &counts {
        println!("| {exit} | {n} |");
    }
    println!("\n| object | category | exit | reasons |\n|---|---|---|---|");
    for o in outcomes.iter().filter(|o| o.exit != "0") {
        println!(
            "| {} | {} | {} | {} |",
            o.object,
            o.category,
            o.exit,
            o.reasons.join("; ")
        );
    }
    let total: f64 = outcomes.iter().map(|o| o.secs).sum();
    println!(
        "\nTime: {:.1} s per object on average, {:.1} s at most.\n",
        total / outcomes.len().max(1) as f64,
        outcomes.iter().map(|o| o.secs).fold(0.0, f64::max)
    );
}

fn median(mut values: Vec<f64>) -> f64 {
    values.retain(|v| v.is_finite());
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn print_categories(outcomes: &[Outcome]) {
    let mut by_category: BTreeMap<&str, Vec<&Outcome>> = BTreeMap::new();
    for o in outcomes {
        by_category.entry(o.category.as_str()).or_default().push(o);
    }
    println!("## Size and mass against typical real objects of the kind\n");
    println!(
        "| category | objects | largest side, median (m) | typical (m) | mass, median (kg) | typical (kg) | within x{MATCH_FACTOR} of typical |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut matched = 0;
    let mut judged = 0;
    let mut misses = Vec::new();
    for (category, rows) in &by_category {
        let prior = CategoryPrior::by_name(category);
        let within = |o: &&&Outcome| {
            prior.is_some_and(|p| {
                let ratio = o.mass_kg / p.mass_kg;
                ratio.is_finite() && (1.0 / MATCH_FACTOR..=MATCH_FACTOR).contains(&ratio)
            })
        };
        let n_within = rows.iter().filter(within).count();
        if prior.is_some() {
            matched += n_within;
            judged += rows.len();
            misses.extend(rows.iter().filter(|o| !within(o)).map(|o| (*o, prior)));
        }
        let typical =
            |f: fn(&CategoryPrior) -> f64| prior.map_or("-".to_owned(), |p| format!("{:.2}", f(p)));
        println!(
            "| {category} | {} | {:.2} | {} | {:.2} | {} | {n_within} of {} |",
            rows.len(),
            median(rows.iter().map(|o| o.largest_side_m).collect()),
            typical(|p| p.largest_side_m),
            median(rows.iter().map(|o| o.mass_kg).collect()),
            typical(|p| p.mass_kg),
            rows.len()
        );
    }
    println!(
        "\n**{matched} of {judged} objects ({:.1} %) within a factor of {MATCH_FACTOR} of their kind's typical mass.**\n",
        100.0 * matched as f64 / judged.max(1) as f64
    );
    println!(
        "| miss | category | largest side (m) | mass (kg) | typical (kg) | ratio |\n|---|---|---|---|---|---|"
    );
    for (o, prior) in misses {
        let typical = prior.map_or(f64::NAN, |p| p.mass_kg);
        println!(
            "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} |",
            o.object,
            o.category,
            o.largest_side_m,
            o.mass_kg,
            typical,
            o.mass_kg / typical
        );
    }
}
