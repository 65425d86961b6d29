//! Rotation consistency: ground truth and prediction rotated together and rested on the ground
//! score like the upright pair (axis and type exactly; pivot distances rescale with the AABB).

mod common;

use uniphys_eval::{AnnotatedAsset, annotated_from_mesh_asset, evaluate_pairs};
use uniphys_geometry::{DMat4, MeshAsset};
use uniphys_mesh_io::{AssetRotation, IngestOptions, load_asset};

fn cabinet_asset(dir: &std::path::Path) -> MeshAsset {
    let loaded = load_asset(&common::cabinet_urdf(dir), &IngestOptions::default()).expect("loads");
    loaded.asset
}

fn rested(mut asset: MeshAsset, rotation: Option<&AssetRotation>) -> (MeshAsset, AnnotatedAsset) {
    if let Some(r) = rotation {
        asset.transform(&DMat4::from_quat(r.rotated_from_input));
    }
    asset.rest_on_ground();
    let annotated = annotated_from_mesh_asset(&asset, "cabinet");
    (asset, annotated)
}

/// The door joint tilted 30 degrees about x and moved 0.05 m along y, before any rotation.
fn wrong_door(mut asset: MeshAsset) -> MeshAsset {
    let door = asset
        .joints
        .iter_mut()
        .find(|j| asset.parts[j.child.0 as usize].name == "door")
        .expect("door joint");
    let tilt = 30f64.to_radians();
    door.axis_in_object = [0.0, tilt.sin(), tilt.cos()];
    door.pivot_in_object_m[1] += 0.05;
    asset
}

#[test]
fn a_perfect_prediction_scores_the_same_upright_and_rotated() {
    let dir = tempfile::tempdir().expect("tempdir");
    let asset = cabinet_asset(dir.path());
    for seed in [1_u64, 2, 3] {
        let rotation = AssetRotation::from_seed(seed);
        let (_, upright) = rested(asset.clone(), None);
        let (_, turned) = rested(asset.clone(), Some(&rotation));
        let a = evaluate_pairs(&[(upright.clone(), upright)]);
        let b = evaluate_pairs(&[(turned.clone(), turned)]);
        for task in ["kinematic_parameters", "articulation_structure"] {
            let (ta, tb) = (a.task(task).expect("task"), b.task(task).expect("task"));
            assert_eq!(ta.counts, tb.counts, "{task}, seed {seed}");
            // acos near 1 turns rounding of the rotated unit vectors into about 1e-6 degrees.
            for (name, value) in &ta.paper_metrics {
                let other = tb.paper(name);
                let value = value.expect("metric present");
                assert!(
                    other.is_some_and(|o| (o - value).abs() < 1e-5),
                    "{task} {name}: {value:?} upright, {other:?} rotated (seed {seed})"
                );
            }
        }
        let k = b.task("kinematic_parameters").expect("task");
        assert!(common::close(k.paper("joint_type_accuracy"), 1.0));
        assert!(common::close(k.paper("pivot_distance_error_aabb_0_2"), 0.0));
    }
}

#[test]
fn a_wrong_prediction_keeps_its_axis_error_and_its_pivot_error_in_metres_when_rotated() {
    let dir = tempfile::tempdir().expect("tempdir");
    let asset = cabinet_asset(dir.path());
    let rotation = AssetRotation::from_seed(7);
    let (_, gt_up) = rested(asset.clone(), None);
    let (_, pred_up) = rested(wrong_door(asset.clone()), None);
    let (gt_asset, gt_rot) = rested(asset.clone(), Some(&rotation));
    let (_, pred_rot) = rested(wrong_door(asset), Some(&rotation));
    let up = evaluate_pairs(&[(pred_up, gt_up.clone())]);
    let rot = evaluate_pairs(&[(pred_rot, gt_rot)]);
    let (ku, kr) = (
        up.task("kinematic_parameters").expect("task"),
        rot.task("kinematic_parameters").expect("task"),
    );
    assert!(common::close(ku.paper("axis_angular_error_degrees"), 15.0));
    assert!(common::close(kr.paper("axis_angular_error_degrees"), 15.0));
    assert!(
        common::close(ku.paper("limit_miou"), 1.0) && common::close(kr.paper("limit_miou"), 1.0)
    );
    // Door: 30 degrees off on one of two joints (the drawer is exact): mean 15. The pivot moved
    // 0.05 m across the hinge line: 0.05 / scale in each frame.
    let scale_up = gt_up.model_frame().expect("frame").scale_m;
    let b = gt_asset.bounds();
    let scale_rot = ((b.max - b.min) / 2.0).max_element();
    assert!(common::close(
        ku.paper("pivot_distance_error_aabb_0_2"),
        0.05 / scale_up
    ));
    assert!(common::close(
        kr.paper("pivot_distance_error_aabb_0_2"),
        0.05 / scale_rot
    ));
}
