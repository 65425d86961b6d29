//! The service commands: `serve` (embedded: API and workers in one process), `api`, `worker`,
//! `migrate`, `tenant`, and the API client commands `submit`, `status` and `dataset export`.

pub mod client;
pub mod config;
pub mod dataset;
mod hooks;
mod manifest;
mod runtime;
pub mod server;
pub mod server_args;
mod tenants;

use std::process::ExitCode;

use config::ServiceArgs;

/// `uniphys migrate`: applies the queue's migrations.
pub fn migrate(args: &ServiceArgs) -> anyhow::Result<ExitCode> {
    server::runtime()?.block_on(async {
        let opened = runtime::open(args, true).await?;
        println!(
            "queue migrations applied on {}",
            runtime::redact(&args.store_config()?.url)
        );
        opened.store.close().await;
        Ok(ExitCode::SUCCESS)
    })
}

/// `uniphys tenant create <name> [--rotate-key]`: creates a tenant and prints a new API key; an
/// existing tenant only with `rotate_key`, which revokes its keys.
pub fn create_tenant(args: &ServiceArgs, name: &str, rotate_key: bool) -> anyhow::Result<ExitCode> {
    server::runtime()?.block_on(async {
        let opened = runtime::open(args, true).await?;
        let (tenant, key) =
            tenants::create_tenant_key(&opened.store, name, "cli", rotate_key).await?;
        eprintln!("{tenant}: new API key (shown once; the service keeps only its digest):");
        println!("{key}");
        opened.store.close().await;
        Ok(ExitCode::SUCCESS)
    })
}

/// `uniphys stage pause|resume|paused`: holds or releases claims of a stage fleet-wide.
pub fn stage_control(
    args: &ServiceArgs,
    action: &str,
    stage: Option<&str>,
) -> anyhow::Result<ExitCode> {
    server::runtime()?.block_on(async {
        let opened = runtime::open(args, false).await?;
        match (action, stage) {
            ("pause", Some(stage)) => {
                let changed = opened.store.pause_stage(stage).await?;
                println!(
                    "{stage}: {}",
                    if changed {
                        "paused"
                    } else {
                        "was already paused"
                    }
                );
            }
            ("resume", Some(stage)) => {
                let changed = opened.store.resume_stage(stage).await?;
                println!(
                    "{stage}: {}",
                    if changed { "resumed" } else { "was not paused" }
                );
            }
            _ => {
                for stage in opened.store.paused_stages().await? {
                    println!("{stage}");
                }
            }
        }
        opened.store.close().await;
        Ok(ExitCode::SUCCESS)
    })
}
