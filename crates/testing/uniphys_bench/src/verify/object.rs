//! One object: ingest, colliders, the verifier on its true joints and on broken ones.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use uniphys_geometry::{
    ConvexParams, DVec3, TriMesh, box_axes, convex_decompositions, parallel_map,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::{CheckOutcome, Joint, JointKind, Provenance};
use uniphys_uniphysgen::CoordinateFrame;
use uniphys_verify::{
    JointVerdict, PatchParams, Scene, SweepParams, articulation_candidates, band_pivots,
    edge_pivots, held_pivots, moving_group, rounded_end_pivots, sweep, verify_joint,
};

use crate::breakage::{Breakage, RangeAgreement, distance_to_line, rotating, same_motion};

/// Surface samples per part, as the pipeline's verify stage.
const SAMPLES_PER_PART: usize = 1500;

/// What happened to one broken joint.
pub(crate) struct BreakResult {
    pub(crate) breakage: Breakage,
    /// The sweep failed the broken joint.
    pub(crate) caught: bool,
    /// The correction gave back the true line, moving the part the true way.
    pub(crate) restored: bool,
    /// ... and a range whose intersection over union with the true one is at least a half.
    pub(crate) restored_range: bool,
    /// The verifier's message.
    pub(crate) message: String,
    /// The deciding sweep's metrics (the correction's when one passed).
    pub(crate) metrics: BTreeMap<String, f64>,
    /// The joint the correction gave, if one passed.
    pub(crate) corrected: Option<Joint>,
}

/// What happened to one true joint.
pub(crate) struct JointResult {
    pub(crate) joint: String,
    /// The true joint, in the object frame the verifier works in.
    pub(crate) truth: Joint,
    pub(crate) kind: JointKind,
    /// The part label from `semantics.txt` (for the tables only; the verifier never sees it).
    pub(crate) label: String,
    pub(crate) outcome: CheckOutcome,
    pub(crate) message: String,
    /// The deciding sweep's metrics (the correction's when one passed).
    pub(crate) metrics: BTreeMap<String, f64>,
    /// A correction replaced the true joint, and the result no longer matches the truth.
    pub(crate) corrected_wrong: bool,
    /// Rotating joints: distance of the nearest pivot candidate to the true axis line, [0,2]
    /// frame; `None` without candidates.
    pub(crate) nearest_pivot_model: Option<f64>,
    /// Time of one 200-step sweep of the true joint alone on one thread, ms.
    pub(crate) sweep_ms: f64,
    pub(crate) breakages: Vec<BreakResult>,
}

impl JointResult {
    /// The true joint passed as it was.
    pub(crate) fn passed_unchanged(&self) -> bool {
        self.outcome == CheckOutcome::Pass
    }
}

/// One object's results.
pub(crate) struct ObjectResult {
    pub(crate) category: String,
    pub(crate) joints: Vec<JointResult>,
    pub(crate) seconds: f64,
}

/// Ingests the object at `dir`, builds its colliders and scene, and judges its joints.
pub(crate) fn judge_object(dir: &Path, breakages: &[Breakage]) -> anyhow::Result<ObjectResult> {
    let start = Instant::now();
    let mut loaded = load_asset(dir, &IngestOptions::default())?;
    loaded.asset.rest_on_ground();
    let asset = loaded.asset;
    let meshes: Vec<TriMesh> = asset.parts.iter().map(|p| p.mesh.clone()).collect();
    // As the pipeline builds them: a shape repeated across parts is decomposed once.
    let parts: Vec<&TriMesh> = meshes.iter().collect();
    let colliders: Vec<Vec<TriMesh>> =
        convex_decompositions(&parts, &ConvexParams::default(), &|_, _| {})?
            .into_iter()
            .collect::<Result<_, _>>()?;
    let scene = Scene::new(&meshes, &colliders, SAMPLES_PER_PART)?;
    let scale = CoordinateFrame::from_object_bounds(asset.bounds()).distance_source_to_model(1.0);
    let labels = read_labels(dir);
    let category = read_category(dir);
    // The true joints, as a grounder would hand them over.
    let truth: Vec<Joint> = asset
        .joints
        .iter()
        .map(|j| Joint {
            provenance: Provenance::Provider {
                name: "ground-truth".into(),
                version: "partnet-mobility".into(),
            },
            ..j.clone()
        })
        .collect();
    let params = SweepParams::default();
    let movable: Vec<usize> = (0..truth.len())
        .filter(|&i| truth[i].kind.is_movable())
        .collect();
    let verdicts = parallel_map(&movable, |&i| {
        verify_joint(&scene, &truth, i, &params, true)
    });
    // One sweep of each true joint, timed alone (the verdicts above ran several at once).
    let mut sweep_ms = Vec::new();
    for &i in &movable {
        let moving = moving_group(&truth, truth[i].child);
        let started = Instant::now();
        sweep(&scene, &truth[i], &moving, &params)?;
        sweep_ms.push(started.elapsed().as_secs_f64() * 1e3);
    }
    let mut joints = Vec::new();
    for ((&i, verdict), sweep_ms) in movable.iter().zip(verdicts).zip(sweep_ms) {
        let verdict = verdict?;
        let joint = &truth[i];
        let child = joint.child.0 as usize;
        let child_points = scene.points_of(&[child]);
        let corrected_wrong = verdict
            .correction
            .as_ref()
            .is_some_and(|(j, _)| !same_motion(j, joint, scale, RangeAgreement::HalfIou));
        let nearest_pivot_model = rotating(joint.kind)
            .then(|| nearest_pivot(&scene, &truth, joint, &child_points))
            .flatten()
            .map(|d| d * scale);
        let broken: Vec<(Breakage, Vec<Joint>)> = breakages
            .iter()
            .filter_map(|&b| {
                let wrong = b.apply(joint, &child_points, scale)?;
                let mut set = truth.clone();
                set[i] = wrong;
                Some((b, set))
            })
            .collect();
        let judged = parallel_map(&broken, |(_, set)| {
            verify_joint(&scene, set, i, &params, true)
        });
        let mut results = Vec::new();
        for ((b, _), v) in broken.iter().zip(judged) {
            let v = v?;
            results.push(BreakResult {
                breakage: *b,
                caught: v.outcome != CheckOutcome::Pass,
                restored: v
                    .correction
                    .as_ref()
                    .is_some_and(|(j, _)| same_motion(j, joint, scale, RangeAgreement::SameWay)),
                restored_range: v
                    .correction
                    .as_ref()
                    .is_some_and(|(j, _)| same_motion(j, joint, scale, RangeAgreement::HalfIou)),
                metrics: with_misfit(&v),
                corrected: v.correction.map(|(j, _)| j),
                message: v.message,
            });
        }
        let label = asset
            .parts
            .get(child)
            .and_then(|p| labels.iter().find(|(link, _)| *link == p.name))
            .map_or_else(String::new, |(_, l)| l.clone());
        joints.push(JointResult {
            joint: joint.name.clone(),
            truth: joint.clone(),
            kind: joint.kind,
            label,
            outcome: verdict.outcome,
            metrics: with_misfit(&verdict),
            message: verdict.message,
            corrected_wrong,
            nearest_pivot_model,
            sweep_ms,
            breakages: results,
        });
    }
    Ok(ObjectResult {
        category,
        joints,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The deciding sweep's metrics by name, with the joint's misfit.
fn with_misfit(verdict: &JointVerdict) -> BTreeMap<String, f64> {
    let mut map = verdict.metrics.as_map();
    map.insert("misfit".to_owned(), verdict.misfit);
    map
}

/// Distance of the pivot candidate nearest to the true axis line, metres.
fn nearest_pivot(
    scene: &Scene,
    joints: &[Joint],
    joint: &Joint,
    child_points: &[DVec3],
) -> Option<f64> {
    let moving = moving_group(joints, joint.child);
    let moving_points = scene.points_of(&moving);
    let parent_points = scene.points_of(&[joint.parent.0 as usize]);
    let part_axes = box_axes(child_points);
    let mut pivots = articulation_candidates(
        &moving_points,
        &parent_points,
        part_axes,
        scene.diagonal_m,
        &PatchParams::default(),
        SweepParams::default().seed,
    )
    .map(|c| c.pivots)
    .unwrap_or_default();
    pivots.extend(edge_pivots(child_points, &parent_points, part_axes));
    let axis = DVec3::from_array(joint.axis_in_object);
    pivots.extend(band_pivots(&moving_points, axis, part_axes));
    pivots.extend(rounded_end_pivots(&moving_points, axis, part_axes));
    pivots.extend(held_pivots(scene, &moving, axis, &SweepParams::default()));
    let on = DVec3::from_array(joint.pivot_in_object_m);
    pivots
        .iter()
        .map(|p| distance_to_line(*p, on, axis))
        .min_by(f64::total_cmp)
}

/// `(link name, part label)` from `semantics.txt`, empty without one.
fn read_labels(dir: &Path) -> Vec<(String, String)> {
    std::fs::read_to_string(dir.join("semantics.txt"))
        .unwrap_or_default()
        .lines()
        .filter_map(|line| {
            let mut words = line.split_whitespace();
            let link = words.next()?;
            let _kind = words.next()?;
            Some((link.to_owned(), words.next().unwrap_or("").to_owned()))
        })
        .collect()
}

/// The category from `meta.json` (`model_cat`), or from the folder's INDEX.tsv row.
fn read_category(dir: &Path) -> String {
    let from_meta = std::fs::read_to_string(dir.join("meta.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v.get("model_cat")?.as_str().map(str::to_owned));
    from_meta
        .or_else(|| {
            let index = std::fs::read_to_string(dir.parent()?.join("INDEX.tsv")).ok()?;
            let name = dir.file_name()?.to_string_lossy().into_owned();
            index
                .lines()
                .find(|l| l.split('\t').next() == Some(name.as_str()))
                .and_then(|l| l.split('\t').nth(4).map(str::to_owned))
        })
        .unwrap_or_else(|| "?".to_owned())
}
