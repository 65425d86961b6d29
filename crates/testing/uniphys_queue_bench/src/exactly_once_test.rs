//! The harness works: both systems run every job exactly once, in the throughput and the
//! latency measurements, idle and under a background load (tiny counts; no timing is asserted).

use std::time::Duration;

use crate::measure::{Probes, Wakeup, check_exactly_once};
use crate::{apalis_runs, uniphys_runs};

const JOBS: u32 = 20;
const WORKERS: u32 = 2;
const POLL: Duration = Duration::from_millis(5);
const BATCH: u32 = 4;

fn probes(load_per_sec: u32) -> Probes {
    Probes {
        workers: WORKERS,
        jobs: JOBS,
        gap: Duration::from_millis(5),
        poll: POLL,
        load_per_sec,
    }
}

fn database_url() -> Option<String> {
    let url = std::env::var("UNIPHYS_TEST_DATABASE_URL").ok();
    if url.is_none() {
        println!("skipped: UNIPHYS_TEST_DATABASE_URL is not set");
    }
    url
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn uniphys_runs_every_job_exactly_once() {
    let Some(url) = database_url() else { return };
    let run = uniphys_runs::throughput(&url, WORKERS, JOBS, BATCH)
        .await
        .expect("uniphys throughput run");
    check_exactly_once(&run.executed, JOBS, "uniphys throughput").expect("exactly once");
    for load in [0, 200] {
        let run = uniphys_runs::latency(&url, probes(load), None)
            .await
            .expect("uniphys latency run");
        check_exactly_once(&run.executed, JOBS, "uniphys latency").expect("exactly once");
        assert_eq!(run.enqueue_to_start_ms.len(), JOBS as usize);
        assert_eq!(run.background_jobs > 0, load > 0);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn apalis_runs_every_job_exactly_once() {
    let Some(url) = database_url() else { return };
    let run = apalis_runs::throughput(&url, WORKERS, JOBS, BATCH, Wakeup::PollRearmed, POLL)
        .await
        .expect("apalis throughput run");
    check_exactly_once(&run.executed, JOBS, "apalis throughput").expect("exactly once");
    // Not `Wakeup::Poll`: apalis's own interval strategy can leave a task waiting for the next
    // heartbeat (30 s), see `rearming_poll`.
    for (wakeup, load) in [
        (Wakeup::PollRearmed, 0),
        (Wakeup::Notify, 0),
        (Wakeup::PollRearmed, 200),
    ] {
        let run = apalis_runs::latency(&url, probes(load), wakeup)
            .await
            .expect("apalis latency run");
        check_exactly_once(&run.executed, JOBS, "apalis latency").expect("exactly once");
        assert_eq!(run.enqueue_to_start_ms.len(), JOBS as usize);
    }
}
