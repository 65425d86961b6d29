//! Loading each mesh format: parts, names, world placement, materials and the service frame.

mod common;

use std::path::Path;

use base64::encode as b64;
use serde_json::json;
use sha2::{Digest, Sha256};
use uniphys_geometry::DVec3;
use uniphys_mesh_io::{IngestOptions, LoadedAsset, load_asset};
use uniphys_types::{SourceFormat, UpAxis};

fn load(path: &Path) -> LoadedAsset {
    load_asset(path, &IngestOptions::default()).expect("fixture loads")
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-6
}

fn has_vertex(positions: &[DVec3], p: DVec3) -> bool {
    positions.iter().any(|q| close(*q, p))
}

#[test]
fn gltf_nodes_become_parts_at_world_positions_converted_to_z_up() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::gltf_fixture(dir.path());
    let loaded = load(&path);
    let parts = &loaded.asset.parts;
    assert_eq!(parts.len(), 2);
    assert_eq!(parts[0].name, "parent");
    assert_eq!(
        parts[1].name, "tri",
        "unnamed node falls back to the mesh name"
    );
    // Y-up (x, y, z) -> Z-up (x, -z, y). Parent at (0, 2, 0); child at (3, 2, 0) in the world.
    assert!(has_vertex(
        &parts[0].mesh.positions,
        DVec3::new(1.0, 0.0, 2.0)
    ));
    assert!(has_vertex(
        &parts[0].mesh.positions,
        DVec3::new(0.0, 0.0, 3.0)
    ));
    assert!(has_vertex(
        &parts[1].mesh.positions,
        DVec3::new(4.0, 0.0, 2.0)
    ));
    assert!(has_vertex(
        &parts[1].mesh.positions,
        DVec3::new(3.0, 0.0, 3.0)
    ));
    // Counter-clockwise in the XY plane of Y-up space faces +Z there, which is -Y after conversion.
    assert!(close(parts[0].mesh.face_normal(0), DVec3::NEG_Y));
    assert_eq!(loaded.source.up_axis, UpAxis::Y);
    assert_eq!(loaded.source.format, SourceFormat::Gltf);
    assert_eq!(loaded.source.file_name, "scene.gltf");
}

#[test]
fn gltf_material_colour_texture_and_uvs_are_read() {
    let dir = tempfile::tempdir().expect("tempdir");
    let loaded = load(&common::gltf_fixture(dir.path()));
    let asset = &loaded.asset;
    assert_eq!(
        asset.materials.len(),
        1,
        "one material shared by both nodes"
    );
    let m = &asset.materials[0];
    assert_eq!(m.name, "paint");
    assert_eq!(m.base_color_rgba, [1.0, 0.5, 0.25, 1.0]);
    assert_eq!(m.base_color_texture, Some(0));
    assert_eq!(asset.textures.len(), 1);
    assert_eq!((asset.textures[0].width, asset.textures[0].height), (2, 2));
    assert_eq!(&asset.textures[0].rgba8[..4], &[200, 0, 0, 255]);
    let mesh = &asset.parts[0].mesh;
    assert_eq!(mesh.face_materials.as_deref(), Some(&[0u32][..]));
    let uvs = mesh.uvs.as_ref().expect("uvs");
    assert!(uvs.contains(&[1.0, 0.0]) && uvs.contains(&[0.0, 1.0]));
}

#[test]
fn content_hash_covers_main_file_then_referenced_files_in_order() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::gltf_fixture(dir.path());
    let loaded = load(&path);
    let mut h = Sha256::new();
    for f in ["scene.gltf", "scene.bin", "tex.png"] {
        h.update(std::fs::read(dir.path().join(f)).expect("read"));
    }
    assert_eq!(loaded.source.content_sha256, hex::encode(h.finalize()));
}

#[test]
fn gltf_with_embedded_data_uris_needs_no_other_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let doc = common::triangle_gltf_json(
        json!({"uri": format!("data:application/octet-stream;base64,{}", b64(common::triangle_bin())), "byteLength": 68}),
        json!({"uri": format!("data:image/png;base64,{}", b64(common::png()))}),
    );
    let path = common::write(
        dir.path(),
        "embedded.gltf",
        serde_json::to_vec(&doc).expect("json"),
    );
    let loaded = load(&path);
    assert_eq!(loaded.asset.parts.len(), 2);
    assert_eq!(loaded.asset.textures.len(), 1);
}

#[test]
fn glb_strip_is_triangulated_lines_skipped_and_view_texture_decoded() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::write(dir.path(), "quad.glb", common::strip_glb());
    let loaded = load(&path);
    assert_eq!(loaded.source.format, SourceFormat::Glb);
    let parts = &loaded.asset.parts;
    assert_eq!(parts.len(), 1);
    assert_eq!(parts[0].name, "quad");
    assert_eq!(
        parts[0].mesh.triangle_count(),
        2,
        "strip of 4 vertices, lines skipped"
    );
    assert!((parts[0].mesh.area() - 1.0).abs() < 1e-9);
    for i in 0..2 {
        assert!(
            close(parts[0].mesh.face_normal(i), DVec3::NEG_Y),
            "consistent strip winding"
        );
    }
    assert_eq!(loaded.asset.textures.len(), 1);
    assert_eq!(loaded.asset.materials[0].base_color_texture, Some(0));
}

#[test]
fn gltf_default_scene_missing_uses_root_nodes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut doc = common::triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    let obj = doc.as_object_mut().expect("object");
    obj.remove("scene");
    obj.remove("scenes");
    common::write(dir.path(), "scene.bin", common::triangle_bin());
    common::write(dir.path(), "tex.png", common::png());
    let path = common::write(
        dir.path(),
        "noscene.gltf",
        serde_json::to_vec(&doc).expect("json"),
    );
    let loaded = load(&path);
    assert_eq!(loaded.asset.parts.len(), 2, "the root node and its child");
}

#[test]
fn obj_groups_become_named_parts_with_mtl_colours_and_texture() {
    let dir = tempfile::tempdir().expect("tempdir");
    let loaded = load(&common::obj_fixture(dir.path()));
    let asset = &loaded.asset;
    let names: Vec<&str> = asset.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["door", "frame"]);
    assert_eq!(asset.parts[0].mesh.triangle_count(), 2, "quad triangulated");
    let colour = |part: usize| {
        let m = asset.parts[part]
            .mesh
            .face_materials
            .as_ref()
            .expect("materials")[0];
        asset.materials[m as usize].clone()
    };
    assert_eq!(colour(0).base_color_rgba, [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(colour(0).base_color_texture, Some(0));
    assert_eq!(colour(1).base_color_rgba, [0.0, 0.0, 1.0, 0.5]);
    assert_eq!(asset.textures.len(), 1);
    // OBJ is Y up by default: the frame triangle at OBJ z = 1 ends at y = -1.
    assert!(has_vertex(
        &asset.parts[1].mesh.positions,
        DVec3::new(0.0, -1.0, 1.0)
    ));
    // v flipped to the glTF convention: OBJ vt (0, 0) becomes (0, 1).
    assert!(
        asset.parts[0]
            .mesh
            .uvs
            .as_ref()
            .expect("uvs")
            .contains(&[0.0, 1.0])
    );
}

#[test]
fn explicit_up_axis_and_unit_scale_are_applied_and_recorded() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::obj_fixture(dir.path());
    let options = IngestOptions {
        up_axis: Some(UpAxis::Z),
        metres_per_unit: 0.01,
        ..IngestOptions::default()
    };
    let loaded = load_asset(&path, &options).expect("loads");
    assert!(has_vertex(
        &loaded.asset.parts[1].mesh.positions,
        DVec3::new(0.0, 0.0, 0.01)
    ));
    assert_eq!(loaded.source.up_axis, UpAxis::Z);
    assert!((loaded.source.metres_per_unit - 0.01).abs() < f64::EPSILON);
}

#[test]
fn ply_ascii_reads_colours_and_fan_triangulates_polygons() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::write(dir.path(), "pyramid.ply", common::pyramid_ply_ascii());
    let loaded = load(&path);
    let mesh = &loaded.asset.parts[0].mesh;
    assert_eq!(loaded.asset.parts[0].name, "pyramid");
    assert_eq!(mesh.triangle_count(), 6, "quad base + 4 sides");
    assert!(mesh.is_closed());
    let colours = mesh.vertex_colors.as_ref().expect("colours");
    assert_eq!(colours[0], [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(colours[4], [0.0, 0.0, 0.0, 1.0]);
    // PLY is Z up: the apex stays on top.
    assert!(close(mesh.positions[4], DVec3::new(0.5, 0.5, 1.0)));
}

#[test]
fn ply_binary_matches_ascii() {
    let dir = tempfile::tempdir().expect("tempdir");
    let a = load(&common::write(
        dir.path(),
        "a.ply",
        common::pyramid_ply_ascii(),
    ));
    let b = load(&common::write(
        dir.path(),
        "b.ply",
        common::pyramid_ply_binary(),
    ));
    assert_eq!(a.asset.parts[0].mesh, b.asset.parts[0].mesh);
}

#[test]
fn stl_ascii_and_binary_cubes_are_welded_closed() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, bytes) in [
        ("ascii.stl", common::cube_stl_ascii().into_bytes()),
        ("binary.stl", common::cube_stl_binary()),
    ] {
        let loaded = load(&common::write(dir.path(), name, bytes));
        let mesh = &loaded.asset.parts[0].mesh;
        assert_eq!(mesh.positions.len(), 8, "{name}: welded");
        assert_eq!(mesh.triangle_count(), 12, "{name}");
        assert!(mesh.is_closed(), "{name}");
        assert!(
            (loaded.asset.bounds().max - DVec3::ONE).length() < 1e-12,
            "{name}: Z up kept"
        );
        assert_eq!(loaded.dropped_degenerate_triangles, 0);
    }
}

#[test]
fn stl_negative_zero_is_welded_with_zero() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = common::cube_stl_ascii().replacen("vertex 0 0 0", "vertex -0 0 0", 1);
    let loaded = load(&common::write(dir.path(), "negzero.stl", text));
    assert!(loaded.asset.parts[0].mesh.is_closed());
}

#[test]
fn latin1_names_in_text_formats_do_not_fail() {
    let dir = tempfile::tempdir().expect("tempdir");
    let obj = b"o t\xfcr\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec();
    let loaded = load(&common::write(dir.path(), "latin1.obj", &obj));
    assert_eq!(loaded.asset.parts[0].name, "t\u{fffd}r");
    let mut stl = common::cube_stl_ascii().into_bytes();
    stl.splice(6..10, b"W\xfcrfel".iter().copied());
    let loaded = load(&common::write(dir.path(), "latin1.stl", stl));
    assert!(loaded.asset.parts[0].mesh.is_closed());
}
