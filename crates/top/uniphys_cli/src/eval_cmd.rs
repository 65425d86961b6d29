//! `uniphys eval`: paper metrics of predictions against ground truth, and with `--per-joint`
//! every true joint next to the predicted one.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use uniphys_eval::{
    JointComparison, compare_joints, evaluate_pairs, load_pairs, per_joint_table, report_tables,
};
use uniphys_mesh_io::{AssetRotation, IngestOptions};

use crate::args::{EvalArgs, metres_per_unit};

pub(crate) fn eval(args: &EvalArgs) -> anyhow::Result<ExitCode> {
    let options = IngestOptions {
        up_axis: args.up.up_axis(),
        metres_per_unit: metres_per_unit(&args.unit)?,
        rotation: args.rotate_seed.map(AssetRotation::from_seed),
        ..IngestOptions::default()
    };
    let pairs =
        load_pairs(&args.pred, &args.gt, &options).context("failed to evaluate the predictions")?;
    let report = evaluate_pairs(&pairs);
    let joints: Option<Vec<JointComparison>> = args.per_joint.then(|| {
        pairs
            .iter()
            .zip(&args.gt)
            .flat_map(|((pred, gt), path)| compare_joints(&asset_name(path), pred, gt))
            .collect()
    });
    if args.json {
        // The report's own fields, and with `--per-joint` a `joints` array beside them.
        let mut output = serde_json::to_value(&report).context("failed to write the report")?;
        if let (Some(joints), Some(fields)) = (&joints, output.as_object_mut()) {
            let joints = serde_json::to_value(joints).context("failed to write the joints")?;
            fields.insert("joints".to_owned(), joints);
        }
        let json = serde_json::to_string_pretty(&output).context("failed to write the report")?;
        println!("{json}");
    } else {
        print!("{}", report_tables(&report));
        if let Some(joints) = &joints {
            print!(
                "\n## Every ground-truth movable joint\n\n{}",
                per_joint_table(joints)
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The asset a ground-truth path names: its folder for a file inside one (`mobility.urdf`,
/// `record.json`), else the file or folder itself.
fn asset_name(path: &Path) -> String {
    let named = if path.is_file() {
        path.parent().filter(|p| !p.as_os_str().is_empty())
    } else {
        Some(path)
    };
    named.and_then(Path::file_name).map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
