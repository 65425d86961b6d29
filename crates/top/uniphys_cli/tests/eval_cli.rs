//! `uniphys eval` and the ingest flags of `uniphys run`, through the binary.

use std::path::Path;
use std::process::{Command, Output};

const CABINET_URDF: &str = r#"<?xml version="1.0"?>
<robot name="cabinet">
  <link name="body"><visual><origin xyz="0 0 0.5"/><geometry><box size="1 1 1"/></geometry></visual></link>
  <link name="door"><visual><origin xyz="0.01 0.5 0.5"/><geometry><box size="0.02 1 1"/></geometry></visual></link>
  <joint name="door_hinge" type="revolute">
    <origin xyz="0.5 -0.5 0"/><parent link="body"/><child link="door"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="1.57" effort="10" velocity="1"/>
  </joint>
</robot>
"#;

fn uniphys(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_uniphys"))
        .args(args)
        .output()
        .expect("run uniphys")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn cabinet(dir: &Path) -> String {
    let folder = dir.join("cabinet");
    std::fs::create_dir_all(&folder).expect("mkdir");
    std::fs::write(folder.join("cabinet.urdf"), CABINET_URDF).expect("write");
    folder.display().to_string()
}

#[test]
fn eval_refuses_unpaired_missing_or_unrecognised_inputs_with_clear_messages() {
    let dir = tempfile::tempdir().expect("tempdir");
    let gt = cabinet(dir.path());
    let o = uniphys(&["eval", "--pred", "a", "b", "--gt", &gt]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("2 predictions but 1 ground truths"),
        "{}",
        stderr(&o)
    );
    let missing = dir.path().join("no_such_run").display().to_string();
    let o = uniphys(&["eval", "--pred", &missing, "--gt", &gt]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no_such_run"), "{}", stderr(&o));
    let o = uniphys(&["eval", "--pred", &gt]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--gt"), "{}", stderr(&o));
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).expect("mkdir");
    let o = uniphys(&["eval", "--pred", &gt, "--gt", &empty.display().to_string()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("record.json"), "{}", stderr(&o));
}

#[test]
fn a_rotated_run_without_joints_is_noted_and_evaluated_in_the_same_frame() {
    let dir = tempfile::tempdir().expect("tempdir");
    let gt = cabinet(dir.path());
    let out = dir.path().join("out");
    let out_s = out.display().to_string();
    let o = uniphys(&[
        "run",
        &gt,
        "--out",
        &out_s,
        "--ignore-joints",
        "--rotate-seed",
        "5",
        "--json",
    ]);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).expect("report"))
            .expect("json");
    let notes: Vec<&str> = report["notes"]
        .as_array()
        .expect("notes")
        .iter()
        .filter_map(|n| n.as_str())
        .collect();
    assert!(
        notes.iter().any(|n| n.contains("ignored the joints")),
        "{notes:?}"
    );
    assert!(notes.iter().any(|n| n.contains("seed 5")), "{notes:?}");

    // `uniphys eval` of the run against its source, in the run's rotated frame.
    let eval_run = |extra: &[&str]| {
        let mut args = vec!["eval", "--pred", &out_s, "--gt", &gt, "--rotate-seed", "5"];
        args.extend_from_slice(extra);
        uniphys(&args)
    };
    let o = eval_run(&["--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let eval: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json report");
    assert_eq!(eval["schema_version"], "uniphys.eval.v1");
    assert_eq!(eval["input_summary"]["gt_movable_joints"], 1);
    let k = &eval["tasks"]["kinematic_parameters"];
    assert!(k["paper_metrics"]["joint_type_accuracy"].is_number(), "{k}");
    assert_eq!(k["counts"]["joint_type"], 1);

    let o = eval_run(&[]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("### kinematic_parameters") && text.contains("| joint_type_accuracy |"),
        "{text}"
    );

    assert!(eval.get("joints").is_none(), "joints only with --per-joint");

    let o = eval_run(&["--json", "--per-joint"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let eval: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json report");
    let joints = eval["joints"].as_array().expect("a joints array");
    assert_eq!(joints.len(), 1, "{joints:?}");
    assert_eq!(joints[0]["asset"], "cabinet");
    assert_eq!(joints[0]["part"], "door");
    assert_eq!(joints[0]["gt_kind"], "revolute");
    assert!(joints[0]["predicted_kind"].is_string(), "{joints:?}");
    let o = eval_run(&["--per-joint"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("| cabinet | door | revolute |"), "{text}");
}

/// The cabinet with its links renamed as a dataset names them: `link_0` the door, `link_1` the
/// body.
fn cabinet_links_urdf() -> String {
    CABINET_URDF
        .replace("\"door\"", "\"link_0\"")
        .replace("\"body\"", "\"link_1\"")
}

#[test]
fn parts_named_otherwise_are_paired_by_shared_surface_when_asked() {
    let dir = tempfile::tempdir().expect("tempdir");
    let source = cabinet(dir.path());
    let gt_dir = dir.path().join("truth");
    std::fs::create_dir_all(&gt_dir).expect("mkdir");
    std::fs::write(gt_dir.join("mobility.urdf"), cabinet_links_urdf()).expect("write");
    let gt = gt_dir.display().to_string();
    let out = dir.path().join("out");
    let out_s = out.display().to_string();
    let o = uniphys(&["run", &source, "--out", &out_s]);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    let eval = |extra: &[&str]| {
        let mut args = vec!["eval", "--pred", &out_s, "--gt", &gt, "--json"];
        args.extend_from_slice(extra);
        let o = uniphys(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).expect("json report")
    };
    // By name nothing pairs: `door` is not `link_0`.
    let by_name = eval(&[]);
    assert_eq!(by_name["input_summary"]["matched_joints"], 0, "{by_name}");
    assert!(by_name.get("part_matches").is_none());
    let by_surface = eval(&["--match-parts", "overlap"]);
    assert_eq!(
        by_surface["input_summary"]["matched_joints"], 1,
        "{by_surface}"
    );
    let parts = by_surface["part_matches"][0]["parts"]
        .as_array()
        .expect("the part matches of the asset");
    let door = parts
        .iter()
        .find(|p| p["gt_part"] == "link_0")
        .expect("the true door is listed");
    assert_eq!(door["pred_part"], "door", "{parts:?}");
    assert!(door["iou"].as_f64().expect("an IoU") > 0.9, "{parts:?}");
    let k = &by_surface["tasks"]["kinematic_parameters"]["paper_metrics"];
    assert_eq!(k["joint_type_accuracy"], 1.0, "{k}");

    // The text report lists the matches; a prediction without its part meshes is refused.
    let text_by_surface = || {
        uniphys(&[
            "eval",
            "--pred",
            &out_s,
            "--gt",
            &gt,
            "--match-parts",
            "overlap",
        ])
    };
    let o = text_by_surface();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("| truth | link_0 | door |"), "{text}");
    std::fs::remove_dir_all(out.join("parts")).expect("remove the part meshes");
    let o = text_by_surface();
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("parts/part_<id>.obj"), "{}", stderr(&o));
}
