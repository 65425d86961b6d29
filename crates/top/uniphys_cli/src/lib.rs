//! The `uniphys` command line: argument parsing and the subcommands.
//!
//! - `uniphys run <asset> --out <dir>`: the whole pipeline on one asset, no servers;
//! - `uniphys export <result> [--format urdf|mjcf|usd|all] [--out <dir>]`: an earlier result
//!   exported again from its own files;
//! - `uniphys measure <mesh>`: exact and voxel mass properties per part, as JSON;
//! - `uniphys points <asset> --out <dir>`: UniPhysGen point clouds (npz) and model frame;
//! - `uniphys eval --pred <record>... --gt <urdf|record|entity>...`: the paper's metrics;
//! - `uniphys examples --out <dir>`: write the example assets as GLB;
//! - `uniphys serve | api | worker | migrate | tenant create | stage pause|resume|paused`: the job-queue service
//!   ([`service`]); `uniphys submit | status`: its API client;
//! - `uniphys stage run decompose <asset> --out <dir>`: one stage alone on a local file.

mod args;
mod eval_cmd;
mod export_cmd;
mod lvlm_args;
mod measure_cmd;
mod out_dir;
mod points_cmd;
mod progress;
mod report_notes;
mod run_cmd;
pub mod service;
mod stage_run_cmd;

pub use args::{
    Cli, Command, EvalArgs, ExportArgs, ExportFormat, StageAction, StageRunArgs, TenantAction,
};
pub use lvlm_args::LvlmArgs;

use std::process::ExitCode;

/// One line for an error and its causes, leaving out causes the message already quotes (the
/// library errors name their cause inline).
#[must_use]
pub fn error_message(error: &anyhow::Error) -> String {
    let mut message = error.to_string();
    for cause in error.chain().skip(1) {
        let cause = cause.to_string();
        if !message.contains(&cause) {
            message = format!("{message}: {cause}");
        }
    }
    message
}

/// Runs a parsed command line; the exit code is 0 on success, 1 if the asset was exported but
/// failed checks.
pub fn execute(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Run(args) => run_cmd::run(&args),
        Command::Export(args) => export_cmd::export(&args),
        Command::Measure {
            mesh,
            voxel_resolution,
        } => measure_cmd::measure(&mesh, voxel_resolution),
        Command::Points(args) => points_cmd::points(&args),
        Command::Eval(args) => eval_cmd::eval(&args),
        Command::Serve(args) => service::server::serve(&args),
        Command::Api(args) => service::server::api(&args),
        Command::Worker(args) => service::server::worker(&args),
        Command::Migrate(args) => service::migrate(&args),
        Command::Tenant {
            action:
                TenantAction::Create {
                    name,
                    rotate_key,
                    service,
                },
        } => service::create_tenant(&service, &name, rotate_key),
        Command::Stage { action } => match action {
            StageAction::Pause { stage, service } => {
                service::stage_control(&service, "pause", Some(&stage))
            }
            StageAction::Resume { stage, service } => {
                service::stage_control(&service, "resume", Some(&stage))
            }
            StageAction::Paused { service } => service::stage_control(&service, "paused", None),
            StageAction::Run { stage, args } => stage_run_cmd::run_stage(&stage, &args),
        },
        Command::Submit(args) => service::client::submit(&args),
        Command::Status(args) => service::client::status(&args),
        Command::Dataset { action } => match action {
            service::dataset::DatasetAction::Export(args) => service::dataset::export(&args),
        },
        Command::Examples { out } => {
            let written = uniphys_examples::write_catalogue(&out).map_err(|e| {
                anyhow::anyhow!(
                    "failed to write the example assets to {}: {e}",
                    out.display()
                )
            })?;
            for path in written {
                println!("{}", path.display());
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
