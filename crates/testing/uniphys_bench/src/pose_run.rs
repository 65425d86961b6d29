//! One pass over the assets in one pose: strip joints, run the pipeline, evaluate.

use std::path::Path;
use std::time::{Duration, Instant};

use uniphys_eval::{
    AnnotatedAsset, EvalReport, PartOverlap, annotated_from_mesh_asset, annotated_from_record,
    evaluate_pairs, load_urdf_ground_truth,
};
use uniphys_geometry::DMat4;
use uniphys_mesh_io::{AssetRotation, IngestOptions};
use uniphys_pipeline::{NoProgress, RunOptions, run};

use crate::assets::{BenchAsset, GroundTruth, Skipped};
use crate::bench_args::BenchArgs;
use crate::decomposed_run::run_decomposed;

/// The pose the assets are given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pose {
    /// As authored (Z up after ingest).
    Upright,
    /// Asset `i` rotated by the uniform random rotation of seed `seed + i`.
    Rotated {
        /// Base seed.
        seed: u64,
    },
}

impl Pose {
    fn rotation(self, index: usize) -> Option<AssetRotation> {
        match self {
            Self::Upright => None,
            Self::Rotated { seed } => {
                Some(AssetRotation::from_seed(seed.wrapping_add(index as u64)))
            }
        }
    }
}

/// The outcome of one asset.
pub(crate) struct AssetRow {
    /// Asset name.
    pub name: String,
    /// The asset's own evaluation.
    pub report: EvalReport,
    /// Wall time of the pipeline run.
    pub run_time: Duration,
    /// Object category, empty if none.
    pub category: String,
    /// The prediction and its ground truth, for the per-joint tables.
    pub pair: (AnnotatedAsset, AnnotatedAsset),
    /// With `--decompose`: the true parts moved by a movable joint that a decomposed part
    /// matches, and how many there are.
    pub recovered: Option<(usize, usize)>,
}

/// The outcome of one pose.
pub(crate) struct PoseResult {
    /// One row per evaluated asset.
    pub rows: Vec<AssetRow>,
    /// All evaluated assets together.
    pub overall: EvalReport,
    /// Per group of assets (examples, PyBullet URDFs): its name, asset count and evaluation.
    pub groups: Vec<(&'static str, usize, EvalReport)>,
    /// Assets whose run or ground truth failed.
    pub skipped: Vec<Skipped>,
    /// Wall time of the whole pose.
    pub wall_time: Duration,
    /// With `--decompose`: movable true parts matched by a decomposed part, of all of them.
    pub recovered: Option<(usize, usize)>,
}

/// Runs every asset in `pose` and evaluates it against its ground truth in the same frame.
/// `scratch` holds the merged meshes and runs of `--decompose`.
pub(crate) fn run_pose(
    assets: &[BenchAsset],
    pose: Pose,
    args: &BenchArgs,
    scratch: &Path,
) -> PoseResult {
    let start = Instant::now();
    let mut rows = Vec::new();
    let mut pairs = Vec::new();
    let mut groups: Vec<(&'static str, Vec<(AnnotatedAsset, AnnotatedAsset)>)> = Vec::new();
    let mut skipped = Vec::new();
    for (index, asset) in assets.iter().enumerate() {
        // The triangle cap keeps the synthetic and PyBullet run short; real objects are
        // judged at their full resolution, as a user would run them.
        let max_triangles = if asset.category.is_empty() {
            args.max_triangles
        } else {
            IngestOptions::default().max_triangles
        };
        let ingest = IngestOptions {
            max_triangles,
            ignore_joints: true,
            rotation: pose.rotation(index),
            ..IngestOptions::default()
        };
        eprintln!("{pose:?}: {}", asset.name);
        let run_start = Instant::now();
        let result = match &asset.ground_truth {
            GroundTruth::Urdf(urdf) if args.decompose => run_decomposed(
                urdf,
                &ingest,
                &scratch.join(format!("decomposed-{index}")),
                args.max_parts,
            )
            .map(|(pred, gt, matches)| {
                let recovered = movable_recovered(&gt, &matches);
                (pred, gt, Some(recovered))
            }),
            _ => run_one(asset, &ingest).map(|(pred, gt)| (pred, gt, None)),
        };
        let run_time = run_start.elapsed();
        match result {
            Ok((pred, gt, recovered)) => {
                let report = evaluate_pairs(&[(pred.clone(), gt.clone())]);
                rows.push(AssetRow {
                    name: asset.name.clone(),
                    report,
                    run_time,
                    category: asset.category.clone(),
                    pair: (pred.clone(), gt.clone()),
                    recovered,
                });
                match groups.iter_mut().find(|(g, _)| *g == asset.group) {
                    Some((_, list)) => list.push((pred.clone(), gt.clone())),
                    None => groups.push((asset.group, vec![(pred.clone(), gt.clone())])),
                }
                pairs.push((pred, gt));
            }
            Err(reason) => skipped.push(Skipped {
                name: format!("{} ({})", asset.name, pose_label(pose)),
                reason,
            }),
        }
    }
    PoseResult {
        overall: evaluate_pairs(&pairs),
        groups: groups
            .iter()
            .map(|(name, list)| (*name, list.len(), evaluate_pairs(list)))
            .collect(),
        skipped,
        wall_time: start.elapsed(),
        recovered: rows
            .iter()
            .filter_map(|r| r.recovered)
            .reduce(|a, b| (a.0 + b.0, a.1 + b.1)),
        rows,
    }
}

/// The true parts moved by a movable joint that a predicted part matches, of all of them.
fn movable_recovered(gt: &AnnotatedAsset, matches: &[PartOverlap]) -> (usize, usize) {
    let movable: Vec<&str> = gt
        .joints
        .iter()
        .filter(|j| j.is_movable())
        .map(|j| j.child.as_str())
        .collect();
    let found = matches
        .iter()
        .filter(|m| m.pred_part.is_some() && movable.contains(&m.gt_part.as_str()))
        .count();
    (found, movable.len())
}

/// Short name of a pose for tables.
pub(crate) fn pose_label(pose: Pose) -> String {
    match pose {
        Pose::Upright => "upright".to_owned(),
        Pose::Rotated { seed } => format!("random SO(3) rotation, seeds {seed} + asset index"),
    }
}

fn run_one(
    asset: &BenchAsset,
    ingest: &IngestOptions,
) -> Result<(AnnotatedAsset, AnnotatedAsset), String> {
    let options = RunOptions {
        ingest: ingest.clone(),
        ..RunOptions::default()
    };
    let output = run(&asset.input, &options, &NoProgress).map_err(|e| e.to_string())?;
    let pred = annotated_from_record(&output.record, &asset.name);
    let gt = match &asset.ground_truth {
        GroundTruth::Example(mesh) => {
            let mut mesh = (**mesh).clone();
            if let Some(r) = &ingest.rotation {
                mesh.transform(&DMat4::from_quat(r.rotated_from_input));
            }
            mesh.rest_on_ground();
            annotated_from_mesh_asset(&mesh, &asset.name)
        }
        GroundTruth::Urdf(path) => {
            load_urdf_ground_truth(path, ingest).map_err(|e| e.to_string())?
        }
    };
    Ok((pred, gt))
}
