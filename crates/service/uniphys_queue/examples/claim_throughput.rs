//! Quick measurement of no-op stage transitions (claim + complete) per second.
//!
//! `cargo run --release -p uniphys_queue --example claim_throughput -- [DATABASE_URL] [RUNS]`
//! With no URL it uses a temporary SQLite file. On Postgres it works in a fresh schema that it
//! drops at the end. Prints enqueue rate and transitions per second for 1, 4 and 16 workers.

use std::time::{Duration, Instant};

use serde_json::json;
use sqlx::Connection;
use uniphys_queue::{JobSpec, NewAsset, QueueStore, StageCost, StoreConfig, WorkerId};

const LEASE: Duration = Duration::from_secs(60);

#[tokio::main(flavor = "multi_thread")]
async fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let url = args.next().filter(|u| !u.is_empty());
    let runs: u32 = args.next().map_or(Ok(2000), |n| n.parse())?;
    let dir = tempfile::tempdir()?;
    for workers in [1_u32, 4, 16] {
        let (config, schema) = match &url {
            Some(url) => {
                let schema = format!("bench_{}_{workers}", std::process::id());
                let mut admin = sqlx::PgConnection::connect(url).await?;
                sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE SCHEMA {schema}")))
                    .execute(&mut admin)
                    .await?;
                (
                    StoreConfig::new(url.clone()).with_schema(schema.clone()),
                    Some(schema),
                )
            }
            None => {
                let path = dir.path().join(format!("bench{workers}.db"));
                (StoreConfig::new(format!("sqlite:{}", path.display())), None)
            }
        };
        let store = QueueStore::connect(&config.with_max_connections(workers + 2)).await?;
        store.migrate().await?;
        let tenant = store.create_tenant("bench").await?;
        let spec = JobSpec::chain(&["noop"]);
        let started = Instant::now();
        for i in 0..runs {
            let asset = NewAsset {
                content_digest: format!("sha256:{i:064x}"),
                source_uri: format!("bench/{i}"),
                size_bytes: 1,
            };
            store.submit(tenant, &asset, &spec).await?;
        }
        let enqueue = started.elapsed();

        let started = Instant::now();
        let mut tasks = Vec::new();
        for w in 0..workers {
            let store = store.clone();
            tasks.push(tokio::spawn(async move {
                let me = WorkerId(format!("bench-{w}"));
                let mut done = 0_u32;
                loop {
                    let claimed = store.claim(&me, &["noop"], LEASE, 1).await?;
                    let Some(run) = claimed.first() else {
                        return Ok::<_, uniphys_queue::QueueError>(done);
                    };
                    store
                        .complete(&run.lease, &json!({}), &StageCost::default())
                        .await?;
                    done += 1;
                }
            }));
        }
        let mut total = 0;
        for task in tasks {
            total += task.await??;
        }
        let elapsed = started.elapsed();
        assert_eq!(total, runs, "every run completed once");
        println!(
            "{:<8} workers={workers:<3} submit {:>7.0}/s   claim+complete {:>7.0}/s ({} runs in {:.2} s)",
            if url.is_some() { "postgres" } else { "sqlite" },
            f64::from(runs) / enqueue.as_secs_f64(),
            f64::from(runs) / elapsed.as_secs_f64(),
            runs,
            elapsed.as_secs_f64(),
        );
        store.close().await;
        if let (Some(url), Some(schema)) = (&url, schema) {
            let mut admin = sqlx::PgConnection::connect(url).await?;
            sqlx::raw_sql(sqlx::AssertSqlSafe(format!("DROP SCHEMA {schema} CASCADE")))
                .execute(&mut admin)
                .await?;
        }
    }
    Ok(())
}
