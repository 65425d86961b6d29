//! `queue-bench`: no-op stage transitions per second (claim + complete) with 1, 4 and 16
//! concurrent workers, and enqueue-to-start latency (p50, p99) on an idle queue, for the UniPhys
//! queue and for apalis 1.0 with apalis-postgres 1.0, on the same PostgreSQL database in one run.
//! Every measurement also checks that each job ran exactly once. Prints Markdown tables.
//!
//! `cargo run --release -p uniphys_queue_bench --bin queue-bench -- --database-url postgres://…`
//! (defaults to `$UNIPHYS_TEST_DATABASE_URL`; `--jobs`, `--workers 1,4,16`, see `--help`).
//! This crate is the only one that depends on apalis.

mod apalis_runs;
mod args;
mod measure;
mod rearming_poll;
mod report;
mod uniphys_runs;

#[cfg(test)]
mod exactly_once_test;

use std::time::Duration;

use clap::Parser as _;
use uniphys_hints::Hints;

use crate::args::BenchArgs;
use crate::measure::{Wakeup, check_exactly_once};

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    let args = BenchArgs::parse();
    let url = args.database_url.as_str();
    let poll = Duration::from_millis(args.poll_ms);
    let gap = Duration::from_millis(args.latency_gap_ms);
    println!(
        "queue-bench: {}; database {}; uniphys_queue vs apalis 1.0 + apalis-postgres 1.0\n",
        report::machine(),
        report::database_host(url)
    );

    let mut throughput = Vec::new();
    for &workers in &args.workers {
        eprintln!("queue-bench: throughput with {workers} workers");
        let ours = uniphys_runs::throughput(url, workers, args.jobs, args.batch).await?;
        check_exactly_once(&ours.executed, args.jobs, "uniphys throughput")?;
        throughput.push(ours);
        let theirs = apalis_runs::throughput(
            url,
            workers,
            args.jobs,
            args.batch,
            Wakeup::PollRearmed,
            poll,
        )
        .await?;
        check_exactly_once(&theirs.executed, args.jobs, "apalis throughput")?;
        throughput.push(theirs);
    }
    println!(
        "No-op stage transitions (claim + complete) per second, each worker fetching up to {} at a \
         time, {} pre-enqueued one-stage jobs per run:\n",
        args.batch, args.jobs
    );
    println!("{}", report::throughput_table(&throughput));

    let mut latency = vec![
        uniphys_runs::latency(
            url,
            args.latency_workers,
            args.latency_jobs,
            gap,
            poll,
            None,
        )
        .await?,
    ];
    if let Some(redis_url) = &args.redis_url {
        eprintln!("queue-bench: uniphys latency, Redis doorbell");
        let hints = Hints::redis(redis_url, &format!("queue-bench-{}", std::process::id()))?;
        latency.push(
            uniphys_runs::latency(
                url,
                args.latency_workers,
                args.latency_jobs,
                gap,
                poll,
                Some(&hints),
            )
            .await?,
        );
    }
    for wakeup in [Wakeup::Poll, Wakeup::PollRearmed, Wakeup::Notify] {
        eprintln!("queue-bench: apalis latency, {}", wakeup.name(args.poll_ms));
        latency.push(
            apalis_runs::latency(
                url,
                args.latency_workers,
                args.latency_jobs,
                gap,
                wakeup,
                poll,
            )
            .await?,
        );
    }
    for run in &latency {
        check_exactly_once(&run.executed, args.latency_jobs, run.system.name())?;
    }
    println!(
        "Enqueue→start latency: {} idle workers, {} jobs submitted one at a time about {} ms apart, \
         measured from calling submit until a worker holds the job:\n",
        args.latency_workers, args.latency_jobs, args.latency_gap_ms
    );
    println!("{}", report::latency_table(&latency, args.poll_ms));
    println!("Done: {}", report::machine());
    Ok(())
}
