//! `uniphys eval`: paper metrics of predictions against ground truth, and with `--per-joint`
//! every true joint next to the predicted one.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context;
use uniphys_eval::{
    JointComparison, MIN_MATCH_IOU, PartOverlap, compare_joints, evaluate_pairs, load_pairs,
    load_pairs_by_overlap, per_joint_table, report_tables,
};
use uniphys_mesh_io::{AssetRotation, IngestOptions};

use crate::args::{EvalArgs, MatchParts, metres_per_unit};

pub(crate) fn eval(args: &EvalArgs) -> anyhow::Result<ExitCode> {
    let options = IngestOptions {
        up_axis: args.up.up_axis(),
        metres_per_unit: metres_per_unit(&args.unit)?,
        rotation: args.rotate_seed.map(AssetRotation::from_seed),
        ..IngestOptions::default()
    };
    let (pairs, part_matches) = match args.match_parts {
        MatchParts::Name => (
            load_pairs(&args.pred, &args.gt, &options)
                .context("failed to evaluate the predictions")?,
            None,
        ),
        MatchParts::Overlap => {
            let matched = load_pairs_by_overlap(&args.pred, &args.gt, &options)
                .context("failed to evaluate the predictions")?;
            let names: Vec<String> = args.gt.iter().map(|g| asset_name(g)).collect();
            let (pairs, matches): (Vec<_>, Vec<_>) = matched.into_iter().unzip();
            (
                pairs,
                Some(names.into_iter().zip(matches).collect::<Vec<_>>()),
            )
        }
    };
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
        if let (Some(matches), Some(fields)) = (&part_matches, output.as_object_mut()) {
            let matches: Vec<serde_json::Value> = matches
                .iter()
                .map(|(asset, m)| serde_json::json!({ "asset": asset, "parts": m }))
                .collect();
            fields.insert("part_matches".to_owned(), serde_json::Value::Array(matches));
        }
        let json = serde_json::to_string_pretty(&output).context("failed to write the report")?;
        println!("{json}");
    } else {
        if let Some(matches) = &part_matches {
            print!("{}", part_match_table(matches));
        }
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

/// Every true part of every asset with the predicted part matched to it by shared surface.
fn part_match_table(matches: &[(String, Vec<PartOverlap>)]) -> String {
    let mut out = format!(
        "## Parts matched by shared surface (IoU at least {MIN_MATCH_IOU})\n\n| asset | true part | predicted part | IoU |\n|---|---|---|---|\n"
    );
    for (asset, parts) in matches {
        for m in parts {
            let pred = m.pred_part.as_deref().unwrap_or("none");
            out.push_str(&format!(
                "| {asset} | {} | {pred} | {:.3} |\n",
                m.gt_part, m.iou
            ));
        }
    }
    out.push('\n');
    out
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
