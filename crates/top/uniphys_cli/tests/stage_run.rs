//! `uniphys stage run decompose` writes the parts of a one-piece input, `uniphys run` ingests its
//! `parts.obj`, and `uniphys run --decompose` replaces the input's parts.

use std::path::Path;
use std::process::{Command, Output};

fn uniphys(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_uniphys"))
        .args(args)
        .output()
        .expect("run uniphys")
}

fn repo_file(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../..")
        .join(path)
        .display()
        .to_string()
}

/// A box with an overhanging lid, as one OBJ object (one piece).
const BOX_WITH_LID_OBJ: &str = "o box_with_lid
v 0 0 0
v 1 0 0
v 1 0.8 0
v 0 0.8 0
v 0 0 0.6
v 1 0 0.6
v 1 0.8 0.6
v 0 0.8 0.6
v -0.03 -0.03 0.6
v 1.03 -0.03 0.6
v 1.03 0.83 0.6
v -0.03 0.83 0.6
v -0.03 -0.03 0.7
v 1.03 -0.03 0.7
v 1.03 0.83 0.7
v -0.03 0.83 0.7
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
f 9 11 10
f 9 12 11
f 13 14 15
f 13 15 16
f 9 10 14
f 9 14 13
f 12 16 15
f 12 15 11
f 9 13 16
f 9 16 12
f 10 11 15
f 10 15 14
";

#[test]
fn stage_run_decompose_writes_parts_that_run_ingests() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("box_with_lid.obj");
    std::fs::write(&input, BOX_WITH_LID_OBJ).expect("write input");
    let out = dir.path().join("decomposed");
    let output = uniphys(&[
        "stage",
        "run",
        "decompose",
        &input.display().to_string(),
        "--out",
        &out.display().to_string(),
        "--up",
        "z",
        "--resolution-px",
        "192",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("24 faces -> 2 parts"), "{stderr}");
    for file in [
        "parts/part_0.obj",
        "parts/part_1.obj",
        "parts.obj",
        "face_parts.json",
        "decompose.json",
    ] {
        assert!(out.join(file).is_file(), "missing {file}");
    }
    let map: Vec<u32> =
        serde_json::from_slice(&std::fs::read(out.join("face_parts.json")).unwrap())
            .expect("face_parts.json is a list");
    let expected: Vec<u32> = (0..24).map(|f| u32::from(f >= 12)).collect();
    assert_eq!(map, expected);

    let run_out = dir.path().join("run");
    let output = uniphys(&[
        "run",
        &out.join("parts.obj").display().to_string(),
        "--out",
        &run_out.display().to_string(),
        "--up",
        "z",
    ]);
    assert!(
        output.status.code() != Some(2),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(run_out.join("record.json")).unwrap())
            .expect("record.json");
    assert_eq!(
        record["parts"].as_array().map(Vec::len),
        Some(2),
        "{record}"
    );
}

#[test]
fn run_with_decompose_replaces_the_parts_of_a_one_piece_input() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("box_with_lid.obj");
    std::fs::write(&input, BOX_WITH_LID_OBJ).expect("write input");
    let run_out = dir.path().join("run");
    let output = uniphys(&[
        "run",
        &input.display().to_string(),
        "--out",
        &run_out.display().to_string(),
        "--up",
        "z",
        "--decompose",
    ]);
    assert!(
        output.status.code() != Some(2),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(run_out.join("record.json")).unwrap())
            .expect("record.json");
    assert_eq!(
        record["parts"].as_array().map(Vec::len),
        Some(2),
        "{record}"
    );
}

#[test]
fn an_unknown_stage_is_refused_with_the_runnable_ones() {
    let output = uniphys(&[
        "stage",
        "run",
        "ground",
        &repo_file("test_data/examples/laptop.glb"),
        "--out",
        "/nonexistent",
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("decompose"), "{stderr}");
}

#[test]
fn an_unreachable_mask_service_fails_with_its_name() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("box_with_lid.obj");
    std::fs::write(&input, BOX_WITH_LID_OBJ).expect("write input");
    // Nothing listens on port 9 of the loopback interface: connections are refused at once.
    let output = uniphys(&[
        "stage",
        "run",
        "decompose",
        &input.display().to_string(),
        "--out",
        &dir.path().join("out").display().to_string(),
        "--resolution-px",
        "64",
        "--views",
        "1",
        "--sam-url",
        "http://127.0.0.1:9",
    ]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.to_lowercase().contains("sam"), "{stderr}");
}
