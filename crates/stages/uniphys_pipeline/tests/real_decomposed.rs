//! The whole raw-mesh path on a real object of the shared PartNet-Mobility set
//! (`../shared/data/partnet-mobility/` beside the repository): the object merged into one bare
//! mesh at rest (no parts, names, colours or joints), run with decomposition and the built-in
//! grounder, its parts paired with the true links by shared surface (`uniphys eval
//! --match-parts overlap`), and its true joints checked through that pairing.
//! `articulation-bench --partnet --decompose` measures the whole set.

use uniphys_decompose::DecomposeOptions;
use uniphys_decompose::output::obj_text;
use uniphys_eval::{
    annotated_from_mesh_asset, load_prediction_with_surfaces, load_urdf_asset,
    match_parts_by_overlap, mesh_asset_part_surfaces, renamed_by_overlap,
};
use uniphys_examples::shared_partnet_object;
use uniphys_geometry::{DVec3, TriMesh};
use uniphys_mesh_io::IngestOptions;
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::UpAxis;

#[test]
fn an_oven_merged_into_one_mesh_comes_back_with_its_knobs_turning() {
    // Eight knobs (continuous joints) on an oven's control panel, and a drawer under it.
    let urdf = shared_partnet_object("kitchen-101921");
    let truth = load_urdf_asset(&urdf, &IngestOptions::default()).expect("ingest the truth");
    let merged = truth.merged();
    let bare = TriMesh {
        positions: merged.positions,
        triangles: merged.triangles,
        ..TriMesh::default()
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("oven.obj");
    std::fs::write(&input, obj_text(&bare)).expect("write the merged mesh");
    let mut options = RunOptions {
        ingest: IngestOptions {
            up_axis: Some(UpAxis::Z),
            ..IngestOptions::default()
        },
        decompose: Some(DecomposeOptions::default()),
        unit_auto: false,
        ..RunOptions::default()
    };
    options.verify.dynamics = None;
    let output = run(&input, &options, &NoProgress).expect("pipeline runs");
    let out = dir.path().join("out");
    for artifact in output
        .artifacts
        .iter()
        .filter(|a| a.path == "record.json" || a.path.starts_with("parts/"))
    {
        let path = out.join(&artifact.path);
        std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
        std::fs::write(&path, &artifact.bytes).expect("write an output file");
    }
    let (pred, pred_surfaces) = load_prediction_with_surfaces(&out).expect("the run's parts");
    let gt = annotated_from_mesh_asset(&truth, "kitchen-101921");
    let matches = match_parts_by_overlap(
        &pred,
        &pred_surfaces,
        &gt,
        &mesh_asset_part_surfaces(&truth),
    )
    .expect("parts matched");
    let pred = renamed_by_overlap(&pred, &matches);
    let knobs: Vec<_> = gt
        .joints
        .iter()
        .filter(|j| j.motion_type == 'C' && j.range == Some([0.0, std::f64::consts::TAU]))
        .collect();
    assert_eq!(knobs.len(), 8, "{:?}", gt.joints);
    let mut wrong = Vec::new();
    for knob in knobs {
        let Some(found) = pred.joint_of(&knob.child) else {
            let m = matches.iter().find(|m| m.gt_part == knob.child);
            wrong.push(format!("{}: no part found for it ({m:?})", knob.child));
            continue;
        };
        let angle = DVec3::from_array(found.axis)
            .normalize()
            .dot(DVec3::from_array(knob.axis).normalize())
            .abs()
            .clamp(0.0, 1.0)
            .acos()
            .to_degrees();
        if found.motion_type != 'C' || angle > 10.0 {
            wrong.push(format!(
                "{}: {} about an axis {angle:.1} deg off",
                knob.child, found.motion_type
            ));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}\nmatches {matches:#?}");
}
