//! Errors about files as a whole: empty, truncated or corrupt, too large, declared sizes that
//! do not fit, unsupported formats and features, options. Messages name the file and the fix.

mod common;

use std::path::Path;
use std::time::Instant;

use serde_json::json;
use uniphys_mesh_io::{IngestError, IngestOptions, detect_format};

#[test]
fn empty_file_is_rejected_naming_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = common::fail(&common::write(dir.path(), "empty.stl", b""));
    assert!(matches!(err, IngestError::Empty { .. }), "{err}");
    common::assert_mentions(&err, &["empty.stl", "empty"]);
}

#[test]
fn truncated_binary_stl_is_a_parse_error_naming_file_and_format() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut bytes = common::cube_stl_binary();
    bytes.truncate(300);
    bytes[0] = b'x'; // not "solid": binary
    let err = common::fail(&common::write(dir.path(), "cut.stl", bytes));
    assert!(
        matches!(err, IngestError::Parse { format: "stl", .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["cut.stl", "stl", "truncated"]);
}

#[test]
fn corrupt_gltf_json_is_a_parse_error_naming_file_and_format() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = common::fail(&common::write(
        dir.path(),
        "bad.gltf",
        b"{\"asset\": {\"version\": ",
    ));
    assert!(
        matches!(err, IngestError::Parse { format: "gltf", .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["bad.gltf", "gltf"]);
}

#[test]
fn too_many_triangles_says_count_limit_and_option() {
    let dir = tempfile::tempdir().expect("tempdir");
    let options = IngestOptions {
        max_triangles: 5,
        ..IngestOptions::default()
    };
    for (name, bytes) in [
        ("bin.stl", common::cube_stl_binary()),
        ("ascii.stl", common::cube_stl_ascii().into_bytes()),
    ] {
        let err = common::fail_with(&common::write(dir.path(), name, bytes), &options);
        assert!(
            matches!(
                err,
                IngestError::TooManyTriangles {
                    count: 12,
                    limit: 5,
                    ..
                }
            ),
            "{err}"
        );
        common::assert_mentions(&err, &[name, "12", "5", "max_triangles"]);
    }
    let err = common::fail_with(
        &common::gltf_fixture(dir.path()),
        &IngestOptions {
            max_triangles: 1,
            ..IngestOptions::default()
        },
    );
    assert!(
        matches!(
            err,
            IngestError::TooManyTriangles {
                count: 2,
                limit: 1,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn file_over_max_file_bytes_is_rejected_before_reading() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::write(dir.path(), "cube.stl", common::cube_stl_binary());
    let options = IngestOptions {
        max_file_bytes: 100,
        ..IngestOptions::default()
    };
    let err = common::fail_with(&path, &options);
    assert!(
        matches!(
            err,
            IngestError::FileTooLarge {
                size: 684,
                limit: 100,
                ..
            }
        ),
        "{err}"
    );
    common::assert_mentions(&err, &["cube.stl", "684", "max_file_bytes"]);
}

#[test]
fn referenced_file_over_the_limit_is_rejected_too() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::obj_fixture(dir.path());
    let padded_mtl = format!("# {}\n{}", "x".repeat(common::OBJ.len()), common::MTL);
    common::write(dir.path(), "parts.mtl", padded_mtl);
    let options = IngestOptions {
        max_file_bytes: u64::try_from(common::OBJ.len()).expect("small"),
        ..IngestOptions::default()
    };
    let err = common::fail_with(&path, &options);
    assert!(matches!(err, IngestError::FileTooLarge { .. }), "{err}");
    common::assert_mentions(&err, &["parts.mtl"]);
}

#[test]
fn unsupported_extension_lists_the_supported_ones() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = common::fail(&common::write(dir.path(), "model.fbx", b"x"));
    assert!(
        matches!(err, IngestError::UnsupportedFormat { .. }),
        "{err}"
    );
    common::assert_mentions(
        &err,
        &[
            "model.fbx",
            ".glb",
            ".gltf",
            ".obj",
            ".ply",
            ".stl",
            ".urdf",
        ],
    );
}

#[test]
fn directory_needs_exactly_one_urdf() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = detect_format(dir.path()).expect_err("no urdf");
    assert!(
        matches!(err, IngestError::NoUrdfInDirectory { .. }),
        "{err}"
    );
    common::write(dir.path(), "a.urdf", "<robot name=\"a\"/>");
    common::write(dir.path(), "b.URDF", "<robot name=\"b\"/>");
    let err = common::fail(dir.path());
    assert!(
        matches!(err, IngestError::SeveralUrdfsInDirectory { .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["a.urdf", "b.URDF"]);
}

#[test]
fn invalid_option_is_rejected_before_reading() {
    let options = IngestOptions {
        metres_per_unit: -1.0,
        ..IngestOptions::default()
    };
    let err = common::fail_with(Path::new("does/not/exist.stl"), &options);
    assert!(
        matches!(
            err,
            IngestError::InvalidOption {
                option: "metres_per_unit",
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn missing_main_file_is_an_io_error_naming_it() {
    let err = common::fail(Path::new("does/not/exist.stl"));
    assert!(matches!(err, IngestError::Io { .. }), "{err}");
    common::assert_mentions(&err, &["exist.stl"]);
}

#[test]
fn sparse_accessor_and_required_draco_are_unsupported() {
    let dir = tempfile::tempdir().expect("tempdir");
    common::write(dir.path(), "scene.bin", common::triangle_bin());
    common::write(dir.path(), "tex.png", common::png());
    let mut doc = common::triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    doc["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    doc["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    let err = common::fail(&common::write(
        dir.path(),
        "draco.gltf",
        serde_json::to_vec(&doc).expect("json"),
    ));
    assert!(matches!(err, IngestError::Unsupported { .. }), "{err}");
    common::assert_mentions(&err, &["draco.gltf", "KHR_draco_mesh_compression"]);

    let mut doc = common::triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    doc["accessors"][0]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": 2, "componentType": 5123},
        "values": {"bufferView": 0}
    });
    let err = common::fail(&common::write(
        dir.path(),
        "sparse.gltf",
        serde_json::to_vec(&doc).expect("json"),
    ));
    assert!(matches!(err, IngestError::Unsupported { .. }), "{err}");
    common::assert_mentions(&err, &["sparse.gltf", "sparse accessor 0"]);
}

#[test]
fn huge_declared_counts_fail_fast_without_allocating() {
    let dir = tempfile::tempdir().expect("tempdir");
    let start = Instant::now();
    // binary STL declaring u32::MAX triangles
    let mut stl = common::cube_stl_binary(); // header starts with "solid", data is binary
    stl[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    let options = IngestOptions {
        max_triangles: usize::MAX,
        ..IngestOptions::default()
    };
    let err = common::fail_with(&common::write(dir.path(), "huge.stl", stl), &options);
    assert!(matches!(err, IngestError::Parse { .. }), "{err}");
    common::assert_mentions(&err, &["4294967295", "truncated"]);
    // PLY declaring a billion vertices (binary)
    let ply = String::from_utf8_lossy(&common::pyramid_ply_binary())
        .replace("element vertex 5", "element vertex 1000000000");
    let mut bytes = common::pyramid_ply_binary();
    let header_end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .expect("header")
        + 11;
    let header = ply[..ply.find("end_header").expect("header") + 11].to_owned();
    bytes.splice(..header_end, header.into_bytes());
    let err = common::fail_with(&common::write(dir.path(), "huge.ply", bytes), &options);
    assert!(
        matches!(err, IngestError::Parse { format: "ply", .. }),
        "{err}"
    );
    // glTF accessor declaring a billion positions
    common::write(dir.path(), "scene.bin", common::triangle_bin());
    common::write(dir.path(), "tex.png", common::png());
    let mut doc = common::triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    doc["accessors"][0]["count"] = json!(1_000_000_000u64);
    let err = common::fail_with(
        &common::write(
            dir.path(),
            "huge.gltf",
            serde_json::to_vec(&doc).expect("json"),
        ),
        &options,
    );
    assert!(
        matches!(err, IngestError::Parse { format: "gltf", .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["accessor 0", "do not fit"]);
    assert!(
        start.elapsed().as_secs_f64() < 2.0,
        "took {:?}",
        start.elapsed()
    );
}

#[test]
fn ply_vertex_count_above_three_times_max_triangles_is_rejected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let options = IngestOptions {
        max_triangles: 1,
        ..IngestOptions::default()
    };
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
               end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    let err = common::fail_with(&common::write(dir.path(), "v.ply", ply), &options);
    assert!(
        matches!(
            err,
            IngestError::TooManyVertices {
                count: 4,
                limit: 3,
                ..
            }
        ),
        "{err}"
    );
}
