//! `uniphys serve`, `uniphys api` and `uniphys worker`: the API and the workers, alone or in
//! one process, until SIGTERM or Ctrl-C (then: stop claiming, drain, release).

use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context;
use tokio_util::sync::CancellationToken;
use tracing::info;
use uniphys_api::{ApiConfig, ApiState};
use uniphys_queue::JobSpec;
use uniphys_telemetry::Metrics;
use uniphys_worker::{Worker, pipeline_job_spec};

use super::hooks::Hooks;
use super::runtime::{Opened, open, telemetry};
use super::server_args::{ApiArgs, ApiOnlyArgs, ServeArgs, WorkerArgs, WorkerOnlyArgs};
use super::tenants::ensure_local_key;

/// The multi-threaded runtime every service command runs on.
pub(crate) fn runtime() -> anyhow::Result<tokio::runtime::Runtime> {
    tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")
}

/// Cancels the token on SIGTERM or Ctrl-C.
fn on_signal(shutdown: CancellationToken) {
    tokio::spawn(async move {
        #[cfg(unix)]
        {
            use tokio::signal::unix::{SignalKind, signal};
            let mut term = match signal(SignalKind::terminate()) {
                Ok(s) => s,
                Err(_) => {
                    let _ = tokio::signal::ctrl_c().await;
                    shutdown.cancel();
                    return;
                }
            };
            tokio::select! {
                _ = term.recv() => {}
                _ = tokio::signal::ctrl_c() => {}
            }
        }
        #[cfg(not(unix))]
        let _ = tokio::signal::ctrl_c().await;
        info!("shutting down: no new claims; running stages finish or are released");
        shutdown.cancel();
    });
}

fn job_spec(stand_ins: &[String]) -> JobSpec {
    if stand_ins.is_empty() {
        pipeline_job_spec()
    } else {
        let names: Vec<&str> = stand_ins.iter().map(String::as_str).collect();
        JobSpec::chain(&names)
    }
}

async fn start_worker(
    opened: &Opened,
    metrics: &Metrics,
    args: &WorkerArgs,
    shutdown: CancellationToken,
) -> anyhow::Result<tokio::task::JoinHandle<()>> {
    let registry = args.registry(&opened.hints, &opened.artifacts)?;
    let config = args.config(&registry)?;
    let worker = Worker::new(
        opened.store.clone(),
        opened.artifacts.clone(),
        opened.hints.clone(),
        metrics.clone(),
        registry,
        config,
    )?;
    // The first line on stdout names this process's worker (operators and the chaos tests read it).
    println!("worker {}", worker.id());
    Ok(tokio::spawn(async move {
        if let Err(e) = worker.run(shutdown).await {
            tracing::error!(error = %e, "the worker stopped");
        }
    }))
}

async fn serve_api(
    opened: &Opened,
    metrics: &Metrics,
    args: &ApiArgs,
    redis: bool,
    spec: JobSpec,
    shutdown: CancellationToken,
) -> anyhow::Result<()> {
    let config = ApiConfig::new(spec)
        .with_max_upload_bytes(args.max_upload_bytes)
        .with_max_backlog_per_tenant(args.max_backlog_per_tenant)
        .with_body_read_timeout(Duration::from_secs(args.body_read_timeout_secs));
    let mut state = ApiState::new(opened.store.clone(), opened.artifacts.clone(), config);
    state.hooks = Arc::new(Hooks {
        hints: opened.hints.clone(),
        metrics: metrics.clone(),
        store: opened.store.clone(),
        redis,
    });
    tokio::spawn(retention_loop(
        opened.store.clone(),
        args.retention(),
        shutdown.clone(),
    ));
    let listener = tokio::net::TcpListener::bind(args.listen)
        .await
        .with_context(|| format!("cannot listen on {}", args.listen))?;
    info!(address = %args.listen, "API listening");
    eprintln!("API on http://{}", args.listen);
    eprintln!(
        "dashboard on http://{}/ui/ (sign in with an API key)",
        args.listen
    );
    let limits = uniphys_api::ConnectionLimits {
        header_read_timeout: Duration::from_secs(args.header_read_timeout_secs),
        max_connections_per_address: args.max_connections_per_address,
    };
    uniphys_api::serve_with_limits(listener, uniphys_api::router(state), limits, async move {
        shutdown.cancelled().await
    })
    .await
    .context("the API server failed")
}

/// Deletes finished jobs past their retention once an hour (the hot tables stay small).
async fn retention_loop(
    store: uniphys_queue::QueueStore,
    policy: uniphys_queue::RetentionPolicy,
    shutdown: CancellationToken,
) {
    let mut tick = tokio::time::interval(std::time::Duration::from_secs(3600));
    loop {
        tokio::select! {
            _ = tick.tick() => {}
            () = shutdown.cancelled() => return,
        }
        match store.purge_finished(&policy).await {
            Ok(report) if report.jobs > 0 => {
                info!(jobs = report.jobs, "retention deleted finished jobs")
            }
            Ok(_) => {}
            Err(e) => tracing::warn!(error = %e, "retention failed; retrying in an hour"),
        }
    }
}

/// `uniphys serve`.
pub fn serve(args: &ServeArgs) -> anyhow::Result<ExitCode> {
    runtime()?.block_on(async {
        let _telemetry = telemetry(&args.service, "uniphys")?;
        let opened = open(&args.service, true).await?;
        let key_file = args.service.api_key_file();
        ensure_local_key(&opened.store, &key_file).await?;
        eprintln!("local API key in {}", key_file.display());
        let metrics = Metrics::new();
        let shutdown = CancellationToken::new();
        on_signal(shutdown.clone());
        let worker = start_worker(&opened, &metrics, &args.worker, shutdown.clone()).await?;
        let redis = args.service.redis_url.is_some();
        let spec = job_spec(&args.worker.stand_ins);
        let api = serve_api(&opened, &metrics, &args.api, redis, spec, shutdown.clone()).await;
        shutdown.cancel();
        worker.await.context("the worker task failed")?;
        opened.store.close().await;
        api.map(|()| ExitCode::SUCCESS)
    })
}

/// `uniphys api`.
pub fn api(args: &ApiOnlyArgs) -> anyhow::Result<ExitCode> {
    runtime()?.block_on(async {
        let _telemetry = telemetry(&args.service, "uniphys-api")?;
        let opened = open(&args.service, false).await?;
        let metrics = Metrics::new();
        let shutdown = CancellationToken::new();
        on_signal(shutdown.clone());
        let redis = args.service.redis_url.is_some();
        let spec = job_spec(&args.stand_ins);
        serve_api(&opened, &metrics, &args.api, redis, spec, shutdown).await?;
        opened.store.close().await;
        Ok(ExitCode::SUCCESS)
    })
}

/// Serves `GET /metrics` of a worker process (stage durations, outcomes, claim latency).
async fn serve_worker_metrics(
    address: std::net::SocketAddr,
    metrics: Metrics,
    shutdown: CancellationToken,
) -> anyhow::Result<()> {
    let listener = tokio::net::TcpListener::bind(address)
        .await
        .with_context(|| format!("cannot listen on {address} for metrics"))?;
    let router = axum::Router::new().route(
        "/metrics",
        axum::routing::get(move || {
            let metrics = metrics.clone();
            async move {
                (
                    [(axum::http::header::CONTENT_TYPE, Metrics::CONTENT_TYPE)],
                    metrics.encode(),
                )
            }
        }),
    );
    tokio::spawn(async move {
        let served = axum::serve(listener, router)
            .with_graceful_shutdown(async move { shutdown.cancelled().await })
            .await;
        if let Err(e) = served {
            tracing::error!(error = %e, "the metrics server stopped");
        }
    });
    Ok(())
}

/// `uniphys worker`.
pub fn worker(args: &WorkerOnlyArgs) -> anyhow::Result<ExitCode> {
    runtime()?.block_on(async {
        let _telemetry = telemetry(&args.service, "uniphys-worker")?;
        let opened = open(&args.service, false).await?;
        let metrics = Metrics::new();
        let shutdown = CancellationToken::new();
        on_signal(shutdown.clone());
        if let Some(address) = args.metrics_listen {
            serve_worker_metrics(address, metrics.clone(), shutdown.clone()).await?;
        }
        start_worker(&opened, &metrics, &args.worker, shutdown)
            .await?
            .await
            .context("the worker task failed")?;
        opened.store.close().await;
        Ok(ExitCode::SUCCESS)
    })
}
