//! The `uniphys` binary as a user meets it: exit codes, messages, output files.

use std::path::Path;
use std::process::Command;

fn uniphys(args: &[&str]) -> std::process::Output {
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

#[test]
fn run_writes_the_simulation_ready_files_and_exits_zero() {
    let out = tempfile::tempdir().expect("tempdir");
    let output = uniphys(&[
        "run",
        &repo_file("test_data/examples/laptop.glb"),
        "--out",
        &out.path().display().to_string(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("laptop: 3 parts, 1 movable joints"),
        "{stdout}"
    );
    assert!(stdout.contains("all checks passed"), "{stdout}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    for stage in ["ingest", "prepare", "ground", "colliders", "export"] {
        assert!(
            stderr.contains(stage),
            "no progress line for {stage}: {stderr}"
        );
    }
    for file in [
        "model.urdf",
        "model.srdf",
        "model.xml",
        "model.usda",
        "report.json",
        "record.json",
        "annotations/object.json",
        "parts/part_0.obj",
        "meshes/part_1_visual.obj",
    ] {
        assert!(out.path().join(file).is_file(), "missing {file}");
    }
}

#[test]
fn a_missing_file_exits_two_with_one_message_naming_it() {
    let output = uniphys(&[
        "run",
        "/nonexistent/chair.glb",
        "--out",
        "/tmp/never-written",
    ]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.starts_with("error: ") && stderr.contains("chair.glb"),
        "{stderr}"
    );
    assert_eq!(
        stderr.matches("No such file or directory").count(),
        1,
        "cause repeated: {stderr}"
    );
    assert!(!Path::new("/tmp/never-written").exists());
}

#[test]
fn an_unknown_unit_is_refused_with_the_accepted_ones() {
    let output = uniphys(&[
        "run",
        &repo_file("test_data/examples/mug.glb"),
        "--out",
        "/tmp/x",
        "--unit",
        "furlong",
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("use auto, m, cm, mm, in, ft"));
}

#[test]
fn measure_prints_exact_and_voxel_volumes_as_json() {
    let output = uniphys(&["measure", &repo_file("test_data/examples/mug.glb")]);
    assert!(output.status.success());
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("json");
    let parts = json["parts"].as_array().expect("parts");
    assert_eq!(parts.len(), 2);
    for p in parts {
        let exact = p["exact"]["volume_m3"]
            .as_f64()
            .expect("closed parts have an exact volume");
        let voxel = p["voxel"]["volume_m3"].as_f64().expect("voxel volume");
        assert!((voxel - exact).abs() / exact < 0.05, "{p}");
    }
}

#[test]
fn tenant_create_refuses_a_bad_name_and_an_existing_tenant_unless_rotating_its_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    let data = dir.path().display().to_string();
    let create = |extra: &[&str]| {
        let mut args = vec!["tenant", "create"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--data-dir", &data]);
        // The store is the SQLite file in `data`, whatever the environment names.
        Command::new(env!("CARGO_BIN_EXE_uniphys"))
            .args(&args)
            .env_remove("UNIPHYS_DATABASE_URL")
            .env_remove("UNIPHYS_DATABASE_SCHEMA")
            .output()
            .expect("run uniphys")
    };
    let first = create(&["acme"]);
    assert_eq!(first.status.code(), Some(0), "{first:?}");
    let key = String::from_utf8_lossy(&first.stdout).trim().to_owned();
    assert!(key.starts_with("uk_"), "{key}");

    let again = create(&["acme"]);
    assert_eq!(again.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(
        stderr.contains("exists") && stderr.contains("--rotate-key"),
        "{stderr}"
    );
    assert!(again.stdout.is_empty(), "no second key is issued");

    let rotated = create(&["acme", "--rotate-key"]);
    assert_eq!(rotated.status.code(), Some(0), "{rotated:?}");
    let new_key = String::from_utf8_lossy(&rotated.stdout).trim().to_owned();
    assert!(new_key.starts_with("uk_") && new_key != key, "{new_key}");

    for bad in ["", "two words", "line\nbreak"] {
        let o = create(&[bad]);
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains("tenant name"), "{bad:?}: {stderr}");
    }
}

#[test]
fn a_worker_refuses_a_stage_it_does_not_run_naming_the_ones_it_does() {
    let dir = tempfile::tempdir().expect("tempdir");
    let output = Command::new(env!("CARGO_BIN_EXE_uniphys"))
        .args(["worker", "--stages", "ingest=2,convrt", "--data-dir"])
        .arg(dir.path())
        .env_remove("UNIPHYS_DATABASE_URL")
        .env_remove("UNIPHYS_DATABASE_SCHEMA")
        .env_remove("UNIPHYS_REDIS_URL")
        .output()
        .expect("run uniphys");
    assert_eq!(output.status.code(), Some(2), "{output:?}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("convrt")
            && stderr.contains("convert, decompose, ground, infer, ingest, verify"),
        "{stderr}"
    );
}
