//! The service commands: `serve` (embedded: API and workers in one process), `api`, `worker`,
//! `migrate`, `tenant`, and the API client commands `submit` and `status`.

pub mod client;
pub mod config;
mod hooks;
mod runtime;
pub mod server;
pub mod server_args;
mod tenants;

use std::process::ExitCode;

use config::ServiceArgs;

/// `uniphys migrate`: applies the queue's migrations.
pub fn migrate(args: &ServiceArgs) -> anyhow::Result<ExitCode> {
    tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?
        .block_on(async {
            let opened = runtime::open(args, true).await?;
            println!(
                "queue migrations applied on {}",
                runtime::redact(&args.store_config()?.url)
            );
            opened.store.close().await;
            Ok(ExitCode::SUCCESS)
        })
}

/// `uniphys tenant create <name>`: creates a tenant (or finds it) and prints a new API key.
pub fn create_tenant(args: &ServiceArgs, name: &str) -> anyhow::Result<ExitCode> {
    tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?
        .block_on(async {
            let opened = runtime::open(args, true).await?;
            let (tenant, key) = tenants::create_tenant_key(&opened.store, name, "cli").await?;
            eprintln!("{tenant}: new API key (shown once; the service keeps only its digest):");
            println!("{key}");
            opened.store.close().await;
            Ok(ExitCode::SUCCESS)
        })
}
