//! `uniphys export`: an earlier result exported again from its own files, without the pipeline.

use std::path::{Path, PathBuf};
use std::process::Command;

fn uniphys(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_uniphys"))
        .args(args)
        .output()
        .expect("run uniphys")
}

/// Fails with the command's stderr unless it succeeded.
fn assert_ok(output: &std::process::Output) {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

fn run_example(name: &str, out: &Path) {
    let asset = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../test_data/examples")
        .join(name);
    let output = uniphys(&[
        "run",
        &asset.display().to_string(),
        "--out",
        &out.display().to_string(),
    ]);
    assert_ok(&output);
}

/// Files under `dir`, relative, sorted.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).expect("read dir") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path.strip_prefix(dir).expect("inside").to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// Text and numbers alternating: the runs of characters a number is written with, and the rest.
fn pieces(text: &str) -> Vec<(bool, &str)> {
    let numeric = |c: char| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E');
    let mut out = Vec::new();
    let mut start = 0;
    let mut in_number = None;
    for (i, c) in text.char_indices() {
        let n = numeric(c);
        if in_number != Some(n) {
            if let Some(was) = in_number {
                out.push((was, &text[start..i]));
            }
            start = i;
            in_number = Some(n);
        }
    }
    if let Some(was) = in_number {
        out.push((was, &text[start..]));
    }
    out
}

/// The same text with the same numbers, to the ten significant digits coordinates are written
/// with (a coordinate read back and moved into its link frame again can differ in the last one).
fn assert_same_text(path: &Path, first: &str, second: &str) {
    let (a, b) = (pieces(first), pieces(second));
    assert_eq!(a.len(), b.len(), "{}: different structure", path.display());
    for ((numeric, x), (_, y)) in a.iter().zip(&b) {
        if x == y {
            continue;
        }
        let (Ok(u), Ok(v)) = (x.parse::<f64>(), y.parse::<f64>()) else {
            panic!("{}: {x:?} became {y:?}", path.display());
        };
        assert!(*numeric, "{}: {x:?} became {y:?}", path.display());
        assert!(
            (u - v).abs() <= 1e-9 * u.abs().max(v.abs()).max(1.0),
            "{}: {u} became {v}",
            path.display()
        );
    }
}

#[test]
fn export_writes_a_result_again_from_its_own_files() {
    let first = tempfile::tempdir().expect("tempdir");
    let second = tempfile::tempdir().expect("tempdir");
    run_example("laptop.glb", first.path());
    let output = uniphys(&[
        "export",
        &first.path().display().to_string(),
        "--out",
        &second.path().display().to_string(),
    ]);
    assert_ok(&output);
    // Every file but the preview render, which the pipeline draws and the export does not.
    let expected: Vec<PathBuf> = files(first.path())
        .into_iter()
        .filter(|p| !p.starts_with("renders"))
        .collect();
    assert_eq!(files(second.path()), expected);
    for path in &expected {
        let a = std::fs::read(first.path().join(path)).expect("first");
        let b = std::fs::read(second.path().join(path)).expect("second");
        match path.extension().and_then(|e| e.to_str()) {
            Some("json") => {
                let (a, b): (serde_json::Value, serde_json::Value) = (
                    serde_json::from_slice(&a).expect("json"),
                    serde_json::from_slice(&b).expect("json"),
                );
                assert_eq!(a, b, "{}", path.display());
            }
            Some("png") => assert_eq!(a, b, "{}", path.display()),
            _ => assert_same_text(
                path,
                &String::from_utf8(a).expect("text"),
                &String::from_utf8(b).expect("text"),
            ),
        }
    }
}

#[test]
fn export_of_one_format_writes_its_model_and_the_files_it_reads() {
    let first = tempfile::tempdir().expect("tempdir");
    run_example("cabinet.glb", first.path());
    for (format, models) in [
        ("usd", &["model.usda"][..]),
        ("urdf", &["model.urdf", "model.srdf"][..]),
        ("mjcf", &["model.xml"][..]),
    ] {
        let out = tempfile::tempdir().expect("tempdir");
        let output = uniphys(&[
            "export",
            &first.path().display().to_string(),
            "--format",
            format,
            "--out",
            &out.path().display().to_string(),
        ]);
        assert_ok(&output);
        let written = files(out.path());
        for model in models {
            assert!(
                written.contains(&PathBuf::from(model)),
                "{format}: {written:?}"
            );
            assert_same_text(
                Path::new(model),
                &std::fs::read_to_string(first.path().join(model)).expect("model"),
                &std::fs::read_to_string(out.path().join(model)).expect("model"),
            );
        }
        for path in &written {
            let is_mesh = path.starts_with("meshes");
            assert!(
                models.iter().any(|m| path == Path::new(m)) || (is_mesh && format != "usd"),
                "{format} wrote {}",
                path.display()
            );
        }
    }
}

#[test]
fn export_of_a_folder_that_is_no_result_says_what_to_give() {
    let empty = tempfile::tempdir().expect("tempdir");
    let output = uniphys(&["export", &empty.path().display().to_string()]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("holds no record.json") && stderr.contains("uniphys run"),
        "{stderr}"
    );
}

#[test]
fn a_whole_export_in_place_removes_what_it_no_longer_writes_and_one_format_keeps_it() {
    let result = tempfile::tempdir().expect("tempdir");
    run_example("cabinet.glb", result.path());
    let before = files(result.path());
    // Files an earlier export wrote and this one does not (a mesh split otherwise, a part gone).
    let stale = ["meshes/part_9_visual_m0.obj", "parts/part_9.obj"];
    for path in stale {
        std::fs::write(result.path().join(path), "o stale\n").expect("stale file");
    }
    let folder = result.path().display().to_string();
    assert_ok(&uniphys(&["export", &folder, "--format", "urdf"]));
    for path in stale {
        assert!(
            result.path().join(path).is_file(),
            "one format removed {path}, which a model it did not rewrite may read"
        );
    }
    let output = uniphys(&["export", &folder]);
    assert_ok(&output);
    assert!(
        String::from_utf8_lossy(&output.stderr).contains("removed 2 files"),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // Nothing else went, and no partial file is left behind.
    assert_eq!(files(result.path()), before);
}
