//! `annotate-bench`: wall time of the LVLM grounding stage on synthetic assets against a local
//! server that answers every request after a fixed delay (a stand-in for a hosted model), with
//! one request in flight at a time and with many, and the time the request images take to
//! render per part.

mod answers;
mod synthetic;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::Parser;
use uniphys_annotate::{AnnotateInput, AnnotateOptions, annotate};
use uniphys_lvlm::{CostLedger, LvlmClient, LvlmConfig, NoCache, NoRateLimit};
use uniphys_replay::{RecordedRequest, ReplayServer, Reply};

use crate::synthetic::{SyntheticAsset, synthetic_asset};

/// Annotate synthetic assets against a local server with a fixed answer delay.
#[derive(Debug, Parser)]
#[command(name = "annotate-bench", about)]
struct Args {
    /// Assets to annotate in each run.
    #[arg(long, default_value_t = 100)]
    assets: usize,
    /// Parts per asset (one or two of them movable).
    #[arg(long, default_value_t = 10)]
    parts: usize,
    /// The server's delay before every answer, milliseconds.
    #[arg(long, default_value_t = 2000)]
    delay_ms: u64,
    /// Concurrency levels to run (assets and requests in flight at once).
    #[arg(long, value_delimiter = ',', default_value = "1,32")]
    concurrency: Vec<usize>,
    /// Side of each render panel, pixels.
    #[arg(long, default_value_t = 384)]
    panel_px: u32,
}

struct RunResult {
    concurrency: usize,
    wall: Duration,
    requests: usize,
    max_in_flight: usize,
    render_secs: f64,
    images: usize,
    cost_usd: f64,
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    anyhow::ensure!(args.parts >= 3, "--parts must be at least 3");
    let assets: Vec<SyntheticAsset> = (0..args.assets)
        .map(|i| synthetic_asset(i, args.parts))
        .collect();
    let mut results = Vec::new();
    for &concurrency in &args.concurrency {
        anyhow::ensure!(concurrency > 0, "concurrency must be positive");
        eprintln!(
            "annotating {} assets at concurrency {concurrency} ...",
            assets.len()
        );
        results.push(run(&assets, concurrency, &args)?);
    }
    print_table(&results, &args);
    Ok(())
}

fn run(assets: &[SyntheticAsset], concurrency: usize, args: &Args) -> anyhow::Result<RunResult> {
    let delay_ms = args.delay_ms;
    let server = ReplayServer::start_with(Arc::new(move |request: &RecordedRequest| {
        let text = answers::answer_text(&request.body_text());
        Reply::json(200, answers::completion(&text)).with_delay_ms(delay_ms)
    }))
    .context("starting the local answer server")?;
    let client = LvlmClient::new(
        LvlmConfig {
            base_url: format!("{}/v1", server.url()),
            model: "bench-model".into(),
            max_concurrency: concurrency,
            request_timeout_secs: 60.0,
            ..LvlmConfig::default()
        },
        Arc::new(NoRateLimit),
        Arc::new(NoCache),
    )?;
    let options = AnnotateOptions {
        panel_px: args.panel_px,
        ..AnnotateOptions::default()
    };
    let next = AtomicUsize::new(0);
    let started = Instant::now();
    let outcomes: Vec<anyhow::Result<(f64, usize, f64)>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..concurrency.min(assets.len()).max(1))
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(asset) = assets.get(i) else { break };
                        let ledger = CostLedger::new(None);
                        let result = annotate(
                            &AnnotateInput {
                                object_name: &asset.name,
                                part_meshes: &asset.meshes,
                                part_colours: &asset.colours,
                                part_names: &asset.names,
                            },
                            &client,
                            &ledger,
                            &options,
                        )
                        .map(|a| {
                            (
                                a.timings.render_secs,
                                a.timings.images,
                                a.cost.total.cost_usd,
                            )
                        })
                        .with_context(|| format!("asset {}", asset.name));
                        done.push(result);
                    }
                    done
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_default())
            .collect()
    });
    let wall = started.elapsed();
    let mut result = RunResult {
        concurrency,
        wall,
        requests: server.requests().len(),
        max_in_flight: server.max_in_flight(),
        render_secs: 0.0,
        images: 0,
        cost_usd: 0.0,
    };
    anyhow::ensure!(
        outcomes.len() == assets.len(),
        "{} of {} assets finished",
        outcomes.len(),
        assets.len()
    );
    for outcome in outcomes {
        let (render_secs, images, cost) = outcome?;
        result.render_secs += render_secs;
        result.images += images;
        result.cost_usd += cost;
    }
    Ok(result)
}

fn print_table(results: &[RunResult], args: &Args) {
    println!(
        "# annotate-bench: {} assets x {} parts, server delay {} ms per answer, panels {} px\n",
        args.assets, args.parts, args.delay_ms, args.panel_px
    );
    println!(
        "| concurrency | requests | peak in flight | wall s | s per asset | speed-up vs first | render ms per part | render ms per image | cost USD |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let first = results.first().map(|r| r.wall.as_secs_f64());
    let total_parts = (args.assets * args.parts).max(1) as f64;
    for r in results {
        let wall = r.wall.as_secs_f64();
        println!(
            "| {} | {} | {} | {:.1} | {:.2} | {:.1}x | {:.1} | {:.1} | {:.2} |",
            r.concurrency,
            r.requests,
            r.max_in_flight,
            wall,
            wall / args.assets.max(1) as f64,
            first.map_or(1.0, |f| f / wall.max(1e-9)),
            1e3 * r.render_secs / total_parts,
            1e3 * r.render_secs / r.images.max(1) as f64,
            r.cost_usd
        );
    }
    println!(
        "\nrender ms per part: all images of an asset (composites, axis and pivot views) summed over threads, divided by its parts; with many assets in flight the threads share the CPU cores."
    );
}
