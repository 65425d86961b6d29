//! Small inputs built in the tests themselves, written into temporary directories.
#![allow(dead_code, reason = "each test binary uses a subset of the fixtures")]

use std::io::Cursor;
use std::path::{Path, PathBuf};

use serde_json::json;
use uniphys_mesh_io::{IngestError, IngestOptions, load_asset};

/// Writes `bytes` to `dir/rel`, creating directories, and returns the path.
pub fn write(dir: &Path, rel: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(rel);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).expect("create fixture directory");
    }
    std::fs::write(&path, bytes).expect("write fixture");
    path
}

/// Corners and outward triangles of the unit cube [0, 1]^3.
pub fn cube() -> (Vec<[f32; 3]>, Vec<[usize; 3]>) {
    let p = |x: f32, y: f32, z: f32| [x, y, z];
    let v = vec![
        p(0.0, 0.0, 0.0),
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(0.0, 0.0, 1.0),
        p(1.0, 0.0, 1.0),
        p(1.0, 1.0, 1.0),
        p(0.0, 1.0, 1.0),
    ];
    let t = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 7, 6],
        [3, 6, 2],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ];
    (v, t)
}

/// The unit cube as ASCII STL (one facet per triangle, vertices repeated).
pub fn cube_stl_ascii() -> String {
    let (v, t) = cube();
    let mut s = String::from("solid cube\n");
    for tri in t {
        s.push_str("  facet normal 0 0 0\n    outer loop\n");
        for i in tri {
            s.push_str(&format!(
                "      vertex {} {} {}\n",
                v[i][0], v[i][1], v[i][2]
            ));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid cube\n");
    s
}

/// The unit cube as binary STL whose header starts with "solid" (as many exporters write).
pub fn cube_stl_binary() -> Vec<u8> {
    let (v, t) = cube();
    let mut b = vec![0u8; 80];
    b[..20].copy_from_slice(b"solid exported by x ");
    b.extend_from_slice(&u32::try_from(t.len()).expect("small").to_le_bytes());
    for tri in t {
        for _ in 0..3 {
            b.extend_from_slice(&0f32.to_le_bytes());
        }
        for i in tri {
            for c in v[i] {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0, 0]);
    }
    b
}

/// Pyramid (square base, 5 vertices, closed) with per-vertex colours; the base is a quad.
pub const PYRAMID_VERTICES: [([f32; 3], [u8; 3]); 5] = [
    ([0.0, 0.0, 0.0], [255, 0, 0]),
    ([1.0, 0.0, 0.0], [0, 255, 0]),
    ([1.0, 1.0, 0.0], [0, 0, 255]),
    ([0.0, 1.0, 0.0], [255, 255, 255]),
    ([0.5, 0.5, 1.0], [0, 0, 0]),
];
/// Faces of the pyramid: the base quad (facing -Z) and four sides.
pub const PYRAMID_FACES: [&[i32]; 5] = [
    &[0, 3, 2, 1],
    &[0, 1, 4],
    &[1, 2, 4],
    &[2, 3, 4],
    &[3, 0, 4],
];

fn ply_header(format: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment pyramid\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 5\n\
         property list uchar int vertex_indices\nend_header\n"
    )
}

/// The pyramid as ASCII PLY.
pub fn pyramid_ply_ascii() -> String {
    let mut s = ply_header("ascii");
    for (p, c) in PYRAMID_VERTICES {
        s.push_str(&format!(
            "{} {} {} {} {} {}\n",
            p[0], p[1], p[2], c[0], c[1], c[2]
        ));
    }
    for f in PYRAMID_FACES {
        let idx: Vec<String> = f.iter().map(ToString::to_string).collect();
        s.push_str(&format!("{} {}\n", f.len(), idx.join(" ")));
    }
    s
}

/// The pyramid as little-endian binary PLY.
pub fn pyramid_ply_binary() -> Vec<u8> {
    let mut b = ply_header("binary_little_endian").into_bytes();
    for (p, c) in PYRAMID_VERTICES {
        for x in p {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.extend_from_slice(&c);
    }
    for f in PYRAMID_FACES {
        b.push(u8::try_from(f.len()).expect("small"));
        for i in f {
            b.extend_from_slice(&i.to_le_bytes());
        }
    }
    b
}

/// A 2x2 PNG.
pub fn png() -> Vec<u8> {
    let img = image::RgbaImage::from_fn(2, 2, |x, y| {
        image::Rgba([
            200,
            u8::try_from(x * 50).expect("small"),
            u8::try_from(y * 50).expect("small"),
            255,
        ])
    });
    let mut out = Vec::new();
    img.write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
        .expect("encode png");
    out
}

/// OBJ with two objects (`door`: a textured quad, `frame`: a triangle) and its MTL.
pub const OBJ: &str = "# two parts\nmtllib parts.mtl\no door\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3 4/4\no frame\nv 0 0 1\nv 1 0 1\nv 0 1 1\n\
usemtl blue\nf 5 6 7\n";
/// MTL of [`OBJ`]: red with a texture, half-transparent blue.
pub const MTL: &str = "newmtl red\nKd 1 0 0\nmap_Kd tex.png\n\nnewmtl blue\nKd 0 0 1\nd 0.5\n";

/// Writes the OBJ, MTL and texture; returns the OBJ path.
pub fn obj_fixture(dir: &Path) -> PathBuf {
    write(dir, "parts.mtl", MTL);
    write(dir, "tex.png", png());
    write(dir, "parts.obj", OBJ)
}

/// Binary data of the glTF triangle: positions (36 bytes), UVs (24), u16 indices (6 + 2 pad).
pub fn triangle_bin() -> Vec<u8> {
    let mut b = Vec::new();
    for c in [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        b.extend_from_slice(&c.to_le_bytes());
    }
    for c in [0f32, 0.0, 1.0, 0.0, 0.0, 1.0] {
        b.extend_from_slice(&c.to_le_bytes());
    }
    for i in [0u16, 1, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b.extend_from_slice(&[0, 0]);
    b
}

/// glTF JSON: node `parent` (translation (0, 2, 0)) with the triangle mesh and an unnamed child
/// (translation (3, 0, 0)) with the same mesh (named `tri`); a textured material.
pub fn triangle_gltf_json(
    buffer: serde_json::Value,
    image: serde_json::Value,
) -> serde_json::Value {
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "parent", "translation": [0.0, 2.0, 0.0], "mesh": 0, "children": [1]},
            {"translation": [3.0, 0.0, 0.0], "mesh": 0}
        ],
        "meshes": [{"name": "tri", "primitives": [{
            "attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0
        }]}],
        "materials": [{"name": "paint", "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 0.5, 0.25, 1.0], "baseColorTexture": {"index": 0}
        }}],
        "textures": [{"source": 0}],
        "images": [image],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 24},
            {"buffer": 0, "byteOffset": 60, "byteLength": 6}
        ],
        "buffers": [buffer]
    })
}

/// Writes `scene.gltf` with external `scene.bin` and `tex.png`; returns the glTF path.
pub fn gltf_fixture(dir: &Path) -> PathBuf {
    write(dir, "scene.bin", triangle_bin());
    write(dir, "tex.png", png());
    let doc = triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    write(
        dir,
        "scene.gltf",
        serde_json::to_vec_pretty(&doc).expect("json"),
    )
}

/// Packs a GLB: 12-byte header, JSON chunk (space padded), BIN chunk (zero padded).
pub fn glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).expect("json");
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let u32le = |n: usize| u32::try_from(n).expect("small").to_le_bytes();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&u32le(total));
    out.extend_from_slice(&u32le(j.len()));
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&u32le(b.len()));
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

/// A GLB holding a unit quad as a TRIANGLE_STRIP (no indices), a LINES primitive that must be
/// skipped, and a PNG base colour texture stored in a buffer view.
pub fn strip_glb() -> Vec<u8> {
    let mut bin = Vec::new();
    for c in [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0] {
        bin.extend_from_slice(&c.to_le_bytes());
    }
    let png = png();
    let png_len = png.len();
    bin.extend_from_slice(&png);
    let doc = json!({
        "asset": {"version": "2.0"},
        "nodes": [{"name": "quad", "mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0}, "mode": 5, "material": 0},
            {"attributes": {"POSITION": 0}, "mode": 1}
        ]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"bufferView": 1, "mimeType": "image/png"}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": png_len}
        ],
        "buffers": [{"byteLength": 48 + png_len}]
    });
    glb(&doc, &bin)
}

/// A door panel in the YZ plane: x = 0, y in [-0.25, 0.25], z in [0, 1].
pub const DOOR_OBJ: &str = "o door\nv 0 -0.25 0\nv 0 0.25 0\nv 0 0.25 1\nv 0 -0.25 1\nf 1 2 3 4\n";

/// A cabinet: base box (visual, centred 0.5 up), a revolute door (OBJ mesh, joint rotated 90
/// degrees about Z, visual offset), a prismatic drawer with only collision geometry.
pub const CABINET_URDF: &str = r#"<?xml version="1.0"?>
<robot name="cabinet">
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base">
    <visual><origin xyz="0 0 0.5"/><geometry><box size="1 1 1"/></geometry><material name="grey"/></visual>
  </link>
  <link name="door">
    <visual><origin xyz="0.25 0 0"/><geometry><mesh filename="meshes/door.obj" scale="1 1 1"/></geometry></visual>
  </link>
  <link name="drawer">
    <collision><geometry><box size="0.4 0.4 0.1"/></geometry></collision>
  </link>
  <joint name="door_hinge" type="revolute">
    <origin xyz="0.5 -0.5 0.5" rpy="0 0 1.5707963267948966"/>
    <parent link="base"/><child link="door"/>
    <axis xyz="1 0 0"/>
    <limit lower="0" upper="1.57" effort="10" velocity="1"/>
    <dynamics damping="0.1" friction="0.2"/>
  </joint>
  <joint name="drawer_slide" type="prismatic">
    <origin xyz="0 0 0.2"/>
    <parent link="base"/><child link="drawer"/>
    <axis xyz="0 2 0"/>
    <limit lower="0" upper="0.3" effort="10" velocity="1"/>
  </joint>
</robot>
"#;

/// Writes the cabinet URDF and its door mesh; returns the URDF path.
pub fn cabinet_fixture(dir: &Path) -> PathBuf {
    write(dir, "meshes/door.obj", DOOR_OBJ);
    write(dir, "cabinet.urdf", CABINET_URDF)
}

/// A PartNet-Mobility style folder: `mobility.urdf` whose root `base` has no geometry, a body
/// `link_1` fixed to it, a door `link_0` revolving on the body; meshes in `textured_objs/`
/// with an MTL whose texture lives in `images/` (`../images/tex.png`); limits without velocity.
pub fn partnet_fixture(dir: &Path) -> PathBuf {
    write(
        dir,
        "textured_objs/original-1.obj",
        "mtllib original-1.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl wood\nf 1/1 2/2 3/3 4/4\n",
    );
    write(
        dir,
        "textured_objs/original-1.mtl",
        "newmtl wood\nKd 0.8 0.6 0.4\nmap_Kd ../images/tex.png\n",
    );
    write(
        dir,
        "textured_objs/original-2.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n",
    );
    write(dir, "images/tex.png", png());
    write(
        dir,
        "mobility.urdf",
        r#"<?xml version="1.0" ?>
<robot name="partnet_1234">
	<link name="base"/>
	<link name="link_0">
		<visual name="door-1">
			<origin xyz="0 0 0"/>
			<geometry><mesh filename="textured_objs/original-1.obj"/></geometry>
		</visual>
	</link>
	<joint name="joint_0" type="revolute">
		<origin xyz="0.5 0 0"/>
		<axis xyz="0 0 -1"/>
		<child link="link_0"/>
		<parent link="link_1"/>
		<limit lower="0.0" upper="1.5707963267948966"/>
	</joint>
	<link name="link_1">
		<visual name="body-2">
			<origin xyz="0 0 0"/>
			<geometry><mesh filename="textured_objs/original-2.obj"/></geometry>
		</visual>
	</link>
	<joint name="joint_1" type="fixed">
		<origin rpy="1.570796326794897 0 -1.570796326794897" xyz="0 0 0"/>
		<child link="link_1"/>
		<parent link="base"/>
	</joint>
</robot>
"#,
    );
    dir.to_path_buf()
}

/// Loads `path` with default options, expecting an error.
pub fn fail(path: &Path) -> IngestError {
    fail_with(path, &IngestOptions::default())
}

/// Loads `path` with `options`, expecting an error.
pub fn fail_with(path: &Path, options: &IngestOptions) -> IngestError {
    match load_asset(path, options) {
        Ok(_) => panic!("{} should not load", path.display()),
        Err(e) => e,
    }
}

/// Asserts the message contains every word and starts lowercase.
pub fn assert_mentions(err: &IngestError, words: &[&str]) {
    let msg = err.to_string();
    for w in words {
        assert!(msg.contains(w), "{w:?} missing from: {msg}");
    }
    assert!(
        !msg.starts_with(char::is_uppercase),
        "lowercase message: {msg}"
    );
}
