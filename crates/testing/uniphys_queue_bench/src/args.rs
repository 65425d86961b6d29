//! Command-line options of `queue-bench`.

/// No-op stage transitions per second (claim + complete) and enqueue-to-start latency of the
/// UniPhys queue and of apalis (apalis-postgres), on the same PostgreSQL database in one run.
#[derive(Debug, clap::Parser)]
#[command(name = "queue-bench", about)]
pub(crate) struct BenchArgs {
    /// PostgreSQL to measure on. The UniPhys queue works in a fresh schema per measurement (dropped
    /// afterwards); apalis uses its own fixed `apalis` schema, one fresh queue name per measurement.
    #[arg(long, env = "UNIPHYS_TEST_DATABASE_URL")]
    pub database_url: String,
    /// Jobs per throughput measurement (each worker count, each system).
    #[arg(long, default_value_t = 2000)]
    pub jobs: u32,
    /// Worker counts of the throughput measurements.
    #[arg(long, value_delimiter = ',', default_values_t = [1_u32, 4, 16, 64])]
    pub workers: Vec<u32>,
    /// Runs a worker fetches at once in the throughput measurements, both systems (apalis's
    /// default `batch_size` is 10; the UniPhys worker claims as many runs as it has free slots).
    #[arg(long, default_value_t = 10)]
    pub batch: u32,
    /// Redis for the UniPhys doorbell's latency row (left out without one).
    #[arg(long, env = "UNIPHYS_TEST_REDIS_URL")]
    pub redis_url: Option<String>,
    /// Jobs per latency measurement, submitted one at a time to an idle queue.
    #[arg(long, default_value_t = 500)]
    pub latency_jobs: u32,
    /// Idle workers waiting during the latency measurement.
    #[arg(long, default_value_t = 4)]
    pub latency_workers: u32,
    /// Mean gap between two latency submissions, milliseconds (varied by ±5 ms so the
    /// submissions do not stay in phase with the pollers).
    #[arg(long, default_value_t = 20)]
    pub latency_gap_ms: u64,
    /// Background jobs a second submitted while the latency is measured under load.
    #[arg(long, default_value_t = 300)]
    pub load_per_sec: u32,
    /// How long a worker that found nothing sleeps before it polls again, milliseconds (both systems).
    #[arg(long, default_value_t = 5)]
    pub poll_ms: u64,
}
