//! Errors about content: non-finite or out-of-range vertex data, degenerate faces, missing or
//! escaping references, unusable URDFs. Messages name the file, the part and the fix.

mod common;

use serde_json::json;
use uniphys_mesh_io::{IngestError, IngestOptions, load_asset};

#[test]
fn nan_coordinate_names_file_part_and_vertex() {
    let dir = tempfile::tempdir().expect("tempdir");
    let obj = "o lid\nv 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n";
    let err = common::fail(&common::write(dir.path(), "nan.obj", obj));
    assert!(
        matches!(err, IngestError::NonFiniteVertex { vertex: 2, .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["nan.obj", "\"lid\"", "vertex 2"]);
}

#[test]
fn infinite_coordinate_in_stl_is_rejected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut bytes = common::cube_stl_binary();
    // first vertex of the first triangle: x = +inf
    bytes[84 + 12..84 + 16].copy_from_slice(&f32::INFINITY.to_le_bytes());
    let err = common::fail(&common::write(dir.path(), "inf.stl", bytes));
    assert!(matches!(err, IngestError::NonFiniteVertex { .. }), "{err}");
    common::assert_mentions(&err, &["inf.stl", "\"inf\"", "vertex 0"]);
    // stl_io already refuses non-finite numbers in ASCII STL.
    let text = common::cube_stl_ascii().replacen("vertex 1 1 1", "vertex inf 1 1", 1);
    let err = common::fail(&common::write(dir.path(), "inf_ascii.stl", text));
    assert!(
        matches!(err, IngestError::Parse { format: "stl", .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["inf_ascii.stl", "finite"]);
}

#[test]
fn only_degenerate_faces_is_an_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               element face 2\nproperty list uchar int vertex_index\nend_header\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n3 0 0 1\n";
    let err = common::fail(&common::write(dir.path(), "flat.ply", ply));
    assert!(matches!(err, IngestError::Degenerate { .. }), "{err}");
    common::assert_mentions(&err, &["flat.ply", "\"flat\"", "non-zero area"]);
}

#[test]
fn degenerate_triangles_among_good_ones_are_dropped_and_counted() {
    let dir = tempfile::tempdir().expect("tempdir");
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\n";
    let loaded = load_asset(
        &common::write(dir.path(), "mixed.obj", obj),
        &IngestOptions::default(),
    )
    .expect("good triangle kept");
    assert_eq!(loaded.dropped_degenerate_triangles, 2);
    assert_eq!(loaded.asset.triangle_count(), 1);
}

#[test]
fn out_of_range_index_names_file_part_and_triangle() {
    let dir = tempfile::tempdir().expect("tempdir");
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n";
    let err = common::fail(&common::write(dir.path(), "idx.ply", ply));
    assert!(
        matches!(
            err,
            IngestError::IndexOutOfRange {
                triangle: 1,
                vertex: 7,
                vertex_count: 3,
                ..
            }
        ),
        "{err}"
    );
    common::assert_mentions(&err, &["idx.ply", "\"idx\"", "triangle 1", "vertex 7"]);
}

#[test]
fn gltf_index_out_of_range_is_reported() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut bin = common::triangle_bin();
    bin[64..66].copy_from_slice(&9u16.to_le_bytes()); // third index -> 9
    common::write(dir.path(), "scene.bin", bin);
    common::write(dir.path(), "tex.png", common::png());
    let doc = common::triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    let err = common::fail(&common::write(
        dir.path(),
        "idx.gltf",
        serde_json::to_vec(&doc).expect("json"),
    ));
    assert!(
        matches!(err, IngestError::IndexOutOfRange { vertex: 9, .. }),
        "{err}"
    );
    common::assert_mentions(&err, &["idx.gltf", "\"parent\"", "triangle 0"]);
}

#[test]
fn a_missing_mtl_or_texture_is_a_warning_but_a_missing_buffer_is_an_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let obj = common::write(
        dir.path(),
        "m.obj",
        "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let loaded = uniphys_mesh_io::load_asset(&obj, &uniphys_mesh_io::IngestOptions::default())
        .expect("geometry loads without its material library");
    assert_eq!(loaded.asset.triangle_count(), 1);
    assert_eq!(loaded.warnings.len(), 1);
    assert!(
        loaded.warnings[0].contains("m.obj") && loaded.warnings[0].contains("gone.mtl"),
        "{:?}",
        loaded.warnings
    );

    // A missing texture image (real downloads often lack some): loaded in its base colour.
    let tex_dir = dir.path().join("t");
    let obj = common::obj_fixture(&tex_dir);
    std::fs::remove_file(tex_dir.join("tex.png")).expect("remove");
    let loaded = uniphys_mesh_io::load_asset(&obj, &uniphys_mesh_io::IngestOptions::default())
        .expect("geometry loads without its texture image");
    assert!(loaded.asset.textures.is_empty());
    assert!(
        loaded
            .asset
            .materials
            .iter()
            .all(|m| m.base_color_texture.is_none()),
        "{:?}",
        loaded.asset.materials
    );
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("parts.mtl") && w.contains("tex.png") && w.contains("base colour")),
        "{:?}",
        loaded.warnings
    );

    let i_dir = dir.path().join("i");
    let gltf = common::gltf_fixture(&i_dir);
    std::fs::remove_file(i_dir.join("tex.png")).expect("remove");
    let loaded = uniphys_mesh_io::load_asset(&gltf, &uniphys_mesh_io::IngestOptions::default())
        .expect("geometry loads without its image");
    assert!(loaded.asset.textures.is_empty());
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("scene.gltf") && w.contains("tex.png")),
        "{:?}",
        loaded.warnings
    );

    let g_dir = dir.path().join("g");
    let gltf = common::gltf_fixture(&g_dir);
    std::fs::remove_file(g_dir.join("scene.bin")).expect("remove");
    let err = common::fail(&gltf);
    assert!(matches!(err, IngestError::MissingReference { .. }), "{err}");
    common::assert_mentions(&err, &["scene.gltf", "scene.bin"]);
}

#[test]
fn references_escaping_the_asset_directory_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    common::write(dir.path(), "secret.mtl", "newmtl s\nKd 1 1 1\n");
    let asset = dir.path().join("asset");
    let obj = common::write(
        &asset,
        "m.obj",
        "mtllib ../secret.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let err = common::fail(&obj);
    assert!(matches!(err, IngestError::PathTraversal { .. }), "{err}");
    common::assert_mentions(&err, &["m.obj", "../secret.mtl", "not read"]);

    for uri in ["../secret.bin", "/etc/passwd", "sub/../../secret.bin"] {
        let doc = common::triangle_gltf_json(
            json!({"uri": uri, "byteLength": 68}),
            json!({"uri": "tex.png"}),
        );
        let gltf = common::write(&asset, "t.gltf", serde_json::to_vec(&doc).expect("json"));
        let err = common::fail(&gltf);
        assert!(
            matches!(err, IngestError::PathTraversal { .. }),
            "{uri}: {err}"
        );
    }

    // URDF: its parent directory is allowed, above it is not.
    let urdf_dir = dir.path().join("pkg/urdf");
    let urdf = r#"<robot name="r"><link name="a"><visual><geometry>
        <mesh filename="../../secret.obj"/></geometry></visual></link></robot>"#;
    common::write(dir.path(), "secret.obj", common::DOOR_OBJ);
    let err = common::fail(&common::write(&urdf_dir, "r.urdf", urdf));
    assert!(matches!(err, IngestError::PathTraversal { .. }), "{err}");
}

#[test]
fn dae_mesh_in_urdf_is_unsupported_naming_the_mesh() {
    let dir = tempfile::tempdir().expect("tempdir");
    let a = dir.path().join("a");
    common::write(&a, "meshes/part.dae", "<COLLADA/>");
    let urdf = r#"<robot name="r"><link name="a"><visual><geometry>
        <mesh filename="meshes/part.dae"/></geometry></visual></link></robot>"#;
    let err = common::fail(&common::write(&a, "r.urdf", urdf));
    assert!(matches!(err, IngestError::Unsupported { .. }), "{err}");
    common::assert_mentions(&err, &["part.dae", "COLLADA"]);
}

#[test]
fn invalid_urdf_structure_is_explained() {
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = r#"<robot name="r"><link name="a"><visual><geometry><box size="1 1 1"/></geometry></visual></link>
        <joint name="j" type="fixed"><parent link="a"/><child link="ghost"/></joint></robot>"#;
    let err = common::fail(&common::write(&dir.path().join("x"), "r.urdf", urdf));
    assert!(matches!(err, IngestError::InvalidUrdf { .. }), "{err}");
    common::assert_mentions(&err, &["r.urdf", "\"ghost\"", "not defined"]);

    let urdf = r#"<robot name="r"><link name="a"><visual><geometry><box size="1 -1 1"/></geometry></visual></link></robot>"#;
    let err = common::fail(&common::write(&dir.path().join("y"), "r.urdf", urdf));
    common::assert_mentions(&err, &["r.urdf", "box size", "positive"]);
}

#[test]
fn urdf_without_geometry_has_no_geometry() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = common::fail(&common::write(
        &dir.path().join("x"),
        "r.urdf",
        "<robot name=\"r\"><link name=\"a\"/></robot>",
    ));
    assert!(matches!(err, IngestError::NoGeometry { .. }), "{err}");
}
