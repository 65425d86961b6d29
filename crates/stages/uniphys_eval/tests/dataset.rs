//! UniPhys-40K entity directories as ground truth (reference 15.2 layout, dataset units).

mod common;

use std::path::Path;

use serde_json::json;
use uniphys_eval::{GroundTruthKind, evaluate_paths, ground_truth_kind, load_ground_truth};
use uniphys_mesh_io::IngestOptions;

fn write_json(path: &Path, value: &serde_json::Value) {
    std::fs::create_dir_all(path.parent().expect("parent")).expect("mkdir");
    std::fs::write(path, serde_json::to_vec(value).expect("json")).expect("write");
}

fn part(name: &str, kinematic: serde_json::Value) -> serde_json::Value {
    json!({
        "index": {"type_name": "t", "entity": "cabinet", "label": "x"},
        "part_level": {"part_name": name, "graspable": true, "affordance": 2},
        "basic_info": {"material": "Wood/oak", "density": 0.7, "young": 10.0, "hardness": 10.197,
                       "poisson": 0.3, "friction": 0.5, "pass_check": true},
        "kinematic_info": kinematic,
    })
}

/// The cabinet of `common` as a UniPhys-40K entity: ids 0..3, door revolute, drawer prismatic
/// with dependency [2, 3], dimensions in cm, box OBJs giving the rested bounds.
fn cabinet_entity(dir: &Path) -> std::path::PathBuf {
    let root = dir.join("entity");
    let a = root.join("annotations");
    write_json(
        &a.join("object.json"),
        &json!({"object_level": {"object_name": "cabinet", "category": "Furniture/Cabinet",
                                 "dimension": [102.0, 100.0, 100.0], "object_mass": 30.0}}),
    );
    let none = json!({"motion_types": [], "motion_info": {}});
    write_json(&a.join("part_0.json"), &part("body", none.clone()));
    write_json(
        &a.join("part_1.json"),
        &part(
            "door",
            json!({"motion_types": ["C"], "motion_info": {
            "C": {"axis": [0, 0, 1], "pos": [0.49, -0.5, 0.0], "range": [0.0, 1.57]},
            "dependency": [1]}}),
        ),
    );
    write_json(
        &a.join("part_2.json"),
        &part(
            "drawer",
            json!({"motion_types": ["B"], "motion_info": {
            "B": {"axis": [1, 0, 0], "pos": [-0.01, 0.0, 0.5], "range": [0.0, 0.3]},
            "dependency": [2, 3]}}),
        ),
    );
    write_json(&a.join("part_3.json"), &part("handle", none));
    let parts = root.join("parts");
    std::fs::create_dir_all(&parts).expect("mkdir");
    std::fs::write(parts.join("part_0.obj"), "v -0.51 -0.5 0\nv 0.49 0.5 1\n").expect("obj");
    std::fs::write(parts.join("part_1.obj"), "v 0.49 -0.5 0\nv 0.51 0.5 1\n").expect("obj");
    root
}

#[test]
fn an_entity_loads_names_groups_units_and_bounds() {
    let dir = tempfile::tempdir().expect("tempdir");
    let root = cabinet_entity(dir.path());
    assert_eq!(
        ground_truth_kind(&root).ok(),
        Some(GroundTruthKind::Dataset)
    );
    let gt = load_ground_truth(&root, &IngestOptions::default()).expect("loads");
    assert_eq!(gt.parts.len(), 4);
    assert_eq!(
        gt.joint_of("drawer").expect("drawer").members,
        ["drawer", "handle"]
    );
    assert_eq!(gt.joint_of("door").expect("door").motion_type, 'C');
    assert!(gt.joint_of("body").is_none());
    assert_eq!(
        gt.bounds_in_object,
        Some([[-0.51, -0.5, 0.0], [0.51, 0.5, 1.0]])
    );
    let object = gt.object.expect("object values");
    let dims = object.dimensions.expect("dimensions");
    assert!(
        common::close(dims.first().copied(), 1.02),
        "cm become metres: {dims:?}"
    );
}

#[test]
fn our_record_against_the_same_cabinet_as_an_entity_scores_perfectly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let root = cabinet_entity(dir.path());
    let out = common::write_record(dir.path(), "run", &common::cabinet_record());
    let report = evaluate_paths(&[out], &[root], &IngestOptions::default()).expect("evaluates");
    let k = report.task("kinematic_parameters").expect("task");
    assert!(common::close(k.paper("joint_type_accuracy"), 1.0));
    assert!(common::close(k.paper("pivot_distance_error_aabb_0_2"), 0.0));
    assert!(common::close(k.paper("limit_miou"), 1.0));
    let s = report.task("articulation_structure").expect("task");
    assert!(common::close(s.paper("structure_miou"), 1.0));
    let p = report.task("intrinsic_physics_part").expect("task");
    assert!(common::close(p.paper("material_accuracy"), 1.0));
    // 700 kg/m^3 is 0.7 g/cm^3; 1e8 Pa is 10.197 HV to the 3 decimals written.
    assert!(common::close(p.paper("density_alde"), 0.0));
    assert_eq!(p.count("records"), 4);
    let o = report.task("intrinsic_physics_object").expect("task");
    assert!(common::close(o.paper("scale_mnre"), 1.0));
    assert!(common::close(o.paper("mass_mnre"), 1.0));
}
