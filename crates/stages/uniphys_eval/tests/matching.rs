//! Loading and matching: a record against itself, a URDF ground truth against a record with
//! deliberate errors, and the input errors of `evaluate_paths`.

mod common;

use common::{CABINET_SCALE_M, cabinet_record, cabinet_urdf, close, write_record};
use uniphys_eval::{EvalError, evaluate_paths, load_ground_truth};
use uniphys_mesh_io::IngestOptions;
use uniphys_types::JointKind;

#[test]
fn a_record_against_itself_scores_perfectly_on_every_task() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = write_record(dir.path(), "run", &cabinet_record());
    let report = evaluate_paths(
        std::slice::from_ref(&out),
        &[out.join("record.json")],
        &IngestOptions::default(),
    )
    .expect("evaluates");
    let k = report.task("kinematic_parameters").expect("task");
    assert!(close(k.paper("joint_type_accuracy"), 1.0));
    assert!(close(k.paper("axis_angular_error_degrees"), 0.0));
    assert!(close(k.paper("pivot_distance_error_aabb_0_2"), 0.0));
    assert!(close(k.paper("limit_miou"), 1.0));
    assert_eq!(
        (k.count("joint_type"), k.count("pivot"), k.count("limit")),
        (2, 1, 2)
    );
    let s = report.task("articulation_structure").expect("task");
    assert!(close(s.paper("structure_miou"), 1.0));
    assert!(close(s.paper("structure_micro_f1"), 1.0));
    assert_eq!(s.count("pairs"), 2);
    let p = report.task("intrinsic_physics_part").expect("task");
    assert!(close(p.paper("material_accuracy"), 1.0));
    assert!(close(p.paper("density_alde"), 0.0));
    assert!(close(p.paper("friction_mae"), 0.0));
    assert!(close(p.paper("affordance_mae"), 0.0));
    assert_eq!(p.count("density"), 4);
    let o = report.task("intrinsic_physics_object").expect("task");
    assert!(close(o.paper("scale_alde"), 0.0));
    assert!(close(o.paper("scale_mnre"), 1.0));
    assert!(close(o.paper("mass_alde"), 0.0));
    assert_eq!(report.input_summary.matched_joints, 2);
    assert_eq!(report.input_summary.extra_pred_movable_joints, 0);
}

#[test]
fn urdf_ground_truth_is_rested_and_groups_fixed_children_with_their_mover() {
    let dir = tempfile::tempdir().expect("tempdir");
    let gt = load_ground_truth(&cabinet_urdf(dir.path()), &IngestOptions::default())
        .expect("urdf loads");
    let door = gt.joint_of("door").expect("door joint");
    assert_eq!(door.motion_type, 'C');
    let pivot = door.pivot_in_object.expect("pivot");
    assert!(
        (pivot[0] - 0.49).abs() < 1e-9 && (pivot[1] + 0.5).abs() < 1e-9,
        "{pivot:?}"
    );
    let drawer = gt.joint_of("drawer").expect("drawer joint");
    assert_eq!(drawer.members, ["drawer", "handle"]);
    let frame = gt.model_frame().expect("bounds known");
    assert!((frame.scale_m - CABINET_SCALE_M).abs() < 1e-9);
    assert!(gt.parts.iter().all(|p| p.physics.is_none()) && gt.object.is_none());
}

#[test]
fn a_wrong_axis_pivot_range_and_type_against_a_urdf_give_the_hand_computed_errors() {
    // Door: axis tilted 30 degrees from +z, pivot 0.102 m off the GT hinge line along y,
    // range [0, 0.785] against [0, 1.57]. Drawer predicted fixed (wrong type), handle joint
    // is not scored.
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = cabinet_urdf(dir.path());
    let mut record = cabinet_record();
    let tilt = 30f64.to_radians();
    record.joints[0].axis_in_object = [0.0, tilt.sin(), tilt.cos()];
    record.joints[0].pivot_in_object_m = [0.49, -0.5 + 0.102, 0.7];
    record.joints[0].limits = Some(uniphys_types::JointLimits {
        lower: 0.0,
        upper: 0.785,
    });
    record.joints[1].kind = JointKind::Fixed;
    record.joints[1].limits = None;
    let out = write_record(dir.path(), "run", &record);
    let report = evaluate_paths(&[out], &[urdf], &IngestOptions::default()).expect("evaluates");
    let k = report.task("kinematic_parameters").expect("task");
    assert!(close(k.paper("joint_type_accuracy"), 0.5));
    assert!(close(k.paper("axis_angular_error_degrees"), 30.0));
    // 0.102 m / 0.51 m per model unit = 0.2 (the 1e-12 of the frame's divisor is below 1e-9).
    assert!(close(k.paper("pivot_distance_error_aabb_0_2"), 0.2));
    assert!(close(k.paper("limit_miou"), 0.5));
    assert_eq!(k.count("missing_prediction"), 0);
    assert_eq!(report.input_summary.gt_movable_joints, 2);
    assert_eq!(report.input_summary.matched_joints, 1);
    let s = report.task("articulation_structure").expect("task");
    assert_eq!((s.count("pairs"), s.count("missing_pair")), (1, 1));
    assert_eq!(
        report
            .task("intrinsic_physics_part")
            .map(|t| t.count("records")),
        Some(0)
    );
}

#[test]
fn a_missing_joint_counts_as_a_missing_prediction_and_a_wrong_type() {
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = cabinet_urdf(dir.path());
    let mut record = cabinet_record();
    // The predicted door part has another name, so no predicted joint moves a part "door";
    // its joint is an extra, unscored one.
    record.parts[1].name = "panel".into();
    let out = write_record(dir.path(), "run", &record);
    let report = evaluate_paths(&[out], &[urdf], &IngestOptions::default()).expect("evaluates");
    let k = report.task("kinematic_parameters").expect("task");
    assert!(close(k.paper("joint_type_accuracy"), 0.5));
    assert_eq!(k.count("missing_prediction"), 1);
    assert_eq!(report.input_summary.extra_pred_movable_joints, 1);
}

#[test]
fn mismatched_or_unreadable_inputs_give_clear_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = write_record(dir.path(), "run", &cabinet_record());
    let options = IngestOptions::default();
    let err = evaluate_paths(std::slice::from_ref(&out), &[], &options).expect_err("no gt");
    assert!(err.to_string().contains("at least one"), "{err}");
    let err = evaluate_paths(
        &[out.clone(), out.clone()],
        std::slice::from_ref(&out),
        &options,
    )
    .expect_err("2 vs 1");
    assert!(
        err.to_string()
            .contains("2 predictions but 1 ground truths"),
        "{err}"
    );
    let missing = dir.path().join("nope");
    let err = evaluate_paths(
        std::slice::from_ref(&missing),
        std::slice::from_ref(&out),
        &options,
    )
    .expect_err("missing pred");
    assert!(
        matches!(err, EvalError::Io { .. }) && err.to_string().contains("nope"),
        "{err}"
    );
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).expect("mkdir");
    let err = evaluate_paths(std::slice::from_ref(&out), &[empty], &options).expect_err("empty gt");
    assert!(err.to_string().contains("is not a ground truth"), "{err}");
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, "{\"x\": 1}").expect("write");
    let err = evaluate_paths(&[bad], std::slice::from_ref(&out), &options).expect_err("bad json");
    assert!(
        err.to_string().contains("record.json (AssetRecord)"),
        "{err}"
    );
}
