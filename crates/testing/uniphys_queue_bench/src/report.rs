//! The tables `queue-bench` prints.

use crate::measure::{LatencyRun, System, ThroughputRun, quantile};

/// `host:port/database` of a PostgreSQL URL (no user, password or parameters).
pub(crate) fn database_host(url: &str) -> &str {
    let rest = url.split_once("://").map_or(url, |(_, rest)| rest);
    let rest = rest.rsplit_once('@').map_or(rest, |(_, host)| host);
    rest.split('?').next().unwrap_or(rest)
}

/// One line about the machine: logical CPUs and, where readable, the load average.
pub(crate) fn machine() -> String {
    let cpus = std::thread::available_parallelism().map_or(0, std::num::NonZero::get);
    let load = std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| l.split_whitespace().next().map(str::to_owned))
        .map_or_else(String::new, |l| format!(", load average (1 min) {l}"));
    format!("nproc {cpus}{load}")
}

/// Throughput table: one row per system and worker count; the ratio is to uniphys at the same
/// worker count (above 1: faster than uniphys).
pub(crate) fn throughput_table(runs: &[ThroughputRun]) -> String {
    let mut out = String::from(
        "| system | workers | jobs | seconds | transitions/s | ratio to uniphys |\n\
         |---|---:|---:|---:|---:|---:|\n",
    );
    for run in runs {
        let ours = runs
            .iter()
            .find(|r| r.system == System::Uniphys && r.workers == run.workers)
            .map(ThroughputRun::transitions_per_sec);
        let ratio = ours.map_or_else(
            || "-".to_owned(),
            |ours| format!("{:.2}", run.transitions_per_sec() / ours),
        );
        out.push_str(&format!(
            "| {} | {} | {} | {:.2} | {:.0} | {ratio} |\n",
            run.system.name(),
            run.workers,
            run.executed.len(),
            run.elapsed.as_secs_f64(),
            run.transitions_per_sec(),
        ));
    }
    out
}

/// Latency table: p50 and p99 from calling submit until a worker holds the probe job; the ratios
/// are to the first uniphys row under the same load (above 1: slower than uniphys).
pub(crate) fn latency_table(runs: &[LatencyRun], poll_ms: u64) -> String {
    let mut out = String::from(
        "| system | wake-up | load jobs/s | background jobs | probes | enqueue→start p50 ms | p99 ms | max ms | p50 ratio to uniphys | p99 ratio | submit call p50 ms |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for run in runs {
        // Compared with the first uniphys row under the same load.
        let ours = runs
            .iter()
            .find(|r| r.system == System::Uniphys && r.load_per_sec == run.load_per_sec);
        let p50 = quantile(&run.enqueue_to_start_ms, 0.5);
        let p99 = quantile(&run.enqueue_to_start_ms, 0.99);
        let (r50, r99) = ours.map_or_else(
            || ("-".to_owned(), "-".to_owned()),
            |o| {
                (
                    format!("{:.2}", p50 / quantile(&o.enqueue_to_start_ms, 0.5)),
                    format!("{:.2}", p99 / quantile(&o.enqueue_to_start_ms, 0.99)),
                )
            },
        );
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {p50:.2} | {p99:.2} | {:.2} | {r50} | {r99} | {:.2} |\n",
            run.system.name(),
            run.wakeup.name(poll_ms),
            run.load_per_sec,
            run.background_jobs,
            run.enqueue_to_start_ms.len(),
            quantile(&run.enqueue_to_start_ms, 1.0),
            quantile(&run.submit_ms, 0.5),
        ));
    }
    for run in runs.iter().filter(|r| r.stuck_workers > 0) {
        out.push_str(&format!(
            "\n{} ({}): {} of the workers did not return within 15 s of being stopped (aborted).\n",
            run.system.name(),
            run.wakeup.name(poll_ms),
            run.stuck_workers,
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn database_host_drops_credentials_and_parameters() {
        assert_eq!(
            database_host("postgres://u:p@127.0.0.1:55432/db?sslmode=disable"),
            "127.0.0.1:55432/db"
        );
        assert_eq!(database_host("postgres://localhost/db"), "localhost/db");
    }
}
