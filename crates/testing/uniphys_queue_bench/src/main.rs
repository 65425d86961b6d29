//! `queue-bench`: no-op stage transitions per second (claim + complete, each worker fetching up
//! to `--batch` runs at once) with 1, 4, 16 and 64 concurrent workers, and enqueue-to-start
//! latency (p50, p99) on an idle queue and under a background load, for the UniPhys queue (its
//! workers polling, or woken by the Redis doorbell) and for apalis 1.0 with apalis-postgres 1.0,
//! on the same PostgreSQL database in one run. Every measurement also checks that each job ran
//! exactly once. Prints Markdown tables.
//!
//! `cargo run --release -p uniphys_queue_bench --bin queue-bench -- --database-url postgres://…`
//! (defaults to `$UNIPHYS_TEST_DATABASE_URL`, Redis to `$UNIPHYS_TEST_REDIS_URL`; `--jobs`,
//! `--workers 1,4,16,64`, `--batch 10`, `--load-per-sec 300`, see `--help`).
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
use crate::measure::{Probes, Wakeup, check_exactly_once};

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

    let hints = args
        .redis_url
        .as_deref()
        .map(|redis| Hints::redis(redis, &format!("queue-bench-{}", std::process::id())))
        .transpose()?;
    let idle = Probes {
        workers: args.latency_workers,
        jobs: args.latency_jobs,
        gap,
        poll,
        load_per_sec: 0,
    };
    let loaded = Probes {
        load_per_sec: args.load_per_sec,
        ..idle
    };
    let mut latency = Vec::new();
    for probes in [idle, loaded] {
        eprintln!(
            "queue-bench: latency with {} background jobs/s",
            probes.load_per_sec
        );
        // Idle: every wake-up of both; under load: each one's fastest.
        let ours: Vec<Option<&Hints>> = match (&hints, probes.load_per_sec) {
            (None, _) => vec![None],
            (Some(h), 0) => vec![None, Some(h)],
            (Some(h), _) => vec![Some(h)],
        };
        for doorbell in ours {
            latency.push(uniphys_runs::latency(url, probes, doorbell).await?);
        }
        let theirs: &[Wakeup] = if probes.load_per_sec == 0 {
            &[Wakeup::Poll, Wakeup::PollRearmed, Wakeup::Notify]
        } else {
            &[Wakeup::Notify]
        };
        for &wakeup in theirs {
            latency.push(apalis_runs::latency(url, probes, wakeup).await?);
        }
    }
    for run in &latency {
        check_exactly_once(&run.executed, args.latency_jobs, run.system.name())?;
    }
    println!(
        "Enqueue→start latency: {} waiting workers, {} probe jobs submitted one at a time about {} \
         ms apart on an idle queue and under a load of {} other jobs a second, measured from \
         calling submit until a worker holds the probe job:\n",
        args.latency_workers, args.latency_jobs, args.latency_gap_ms, args.load_per_sec
    );
    println!("{}", report::latency_table(&latency, args.poll_ms));
    println!("Done: {}", report::machine());
    Ok(())
}
