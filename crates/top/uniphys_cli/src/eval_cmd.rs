//! `uniphys eval`: paper metrics of predictions against ground truth.

use std::process::ExitCode;

use anyhow::Context;
use uniphys_eval::{evaluate_paths, report_tables};
use uniphys_mesh_io::{AssetRotation, IngestOptions};

use crate::args::{EvalArgs, metres_per_unit};

pub(crate) fn eval(args: &EvalArgs) -> anyhow::Result<ExitCode> {
    let options = IngestOptions {
        up_axis: args.up.up_axis(),
        metres_per_unit: metres_per_unit(&args.unit)?,
        rotation: args.rotate_seed.map(AssetRotation::from_seed),
        ..IngestOptions::default()
    };
    let report = evaluate_paths(&args.pred, &args.gt, &options)
        .context("failed to evaluate the predictions")?;
    if args.json {
        let json = serde_json::to_string_pretty(&report).context("failed to write the report")?;
        println!("{json}");
    } else {
        print!("{}", report_tables(&report));
    }
    Ok(ExitCode::SUCCESS)
}
