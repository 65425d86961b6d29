//! Fuzz-style robustness: truncated and byte-corrupted versions of a valid small file of every
//! accepted format must load or fail with an error, never panic, and finish quickly.

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde_json::json;
use uniphys_mesh_io::{IngestOptions, load_asset};

const TIME_LIMIT: Duration = Duration::from_secs(2);

/// A valid asset: its files, the file to damage, and the path to load.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    target: &'static str,
    load: &'static str,
}

fn cases() -> Vec<Case> {
    let gltf_doc = common::triangle_gltf_json(
        json!({"uri": "scene.bin", "byteLength": 68}),
        json!({"uri": "tex.png"}),
    );
    let gltf_files = vec![
        ("scene.gltf", serde_json::to_vec(&gltf_doc).expect("json")),
        ("scene.bin", common::triangle_bin()),
        ("tex.png", common::png()),
    ];
    let obj_files = vec![
        ("parts.obj", common::OBJ.as_bytes().to_vec()),
        ("parts.mtl", common::MTL.as_bytes().to_vec()),
        ("tex.png", common::png()),
    ];
    let urdf_files = vec![
        ("cabinet.urdf", common::CABINET_URDF.as_bytes().to_vec()),
        ("meshes/door.obj", common::DOOR_OBJ.as_bytes().to_vec()),
    ];
    vec![
        Case {
            name: "stl_ascii",
            files: vec![("m.stl", common::cube_stl_ascii().into_bytes())],
            target: "m.stl",
            load: "m.stl",
        },
        Case {
            name: "stl_binary",
            files: vec![("m.stl", common::cube_stl_binary())],
            target: "m.stl",
            load: "m.stl",
        },
        Case {
            name: "ply_ascii",
            files: vec![("m.ply", common::pyramid_ply_ascii().into_bytes())],
            target: "m.ply",
            load: "m.ply",
        },
        Case {
            name: "ply_binary",
            files: vec![("m.ply", common::pyramid_ply_binary())],
            target: "m.ply",
            load: "m.ply",
        },
        Case {
            name: "obj",
            files: obj_files.clone(),
            target: "parts.obj",
            load: "parts.obj",
        },
        Case {
            name: "mtl",
            files: obj_files.clone(),
            target: "parts.mtl",
            load: "parts.obj",
        },
        Case {
            name: "png",
            files: obj_files,
            target: "tex.png",
            load: "parts.obj",
        },
        Case {
            name: "gltf",
            files: gltf_files.clone(),
            target: "scene.gltf",
            load: "scene.gltf",
        },
        Case {
            name: "gltf_bin",
            files: gltf_files,
            target: "scene.bin",
            load: "scene.gltf",
        },
        Case {
            name: "glb",
            files: vec![("m.glb", common::strip_glb())],
            target: "m.glb",
            load: "m.glb",
        },
        Case {
            name: "urdf",
            files: urdf_files.clone(),
            target: "cabinet.urdf",
            load: "cabinet.urdf",
        },
        Case {
            name: "urdf_mesh",
            files: urdf_files,
            target: "meshes/door.obj",
            load: "cabinet.urdf",
        },
    ]
}

/// Deterministic linear congruential generator (Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
    fn below(&mut self, n: usize) -> usize {
        usize::try_from(self.next()).expect("64-bit") % n
    }
}

/// Every length for small files, else about 200 evenly spaced lengths.
fn truncation_lengths(len: usize) -> Vec<usize> {
    if len < 400 {
        (0..len).collect()
    } else {
        (0..200).map(|i| i * len / 200).collect()
    }
}

/// About 200 corrupted copies: single bit flips, overwrites with special bytes, random bytes.
fn corruptions(bytes: &[u8], seed: u64) -> Vec<Vec<u8>> {
    let mut rng = Lcg(seed);
    (0..200)
        .map(|i| {
            let mut b = bytes.to_vec();
            let at = rng.below(b.len());
            b[at] = match i % 4 {
                0 => b[at] ^ (1 << rng.below(8)),
                1 => [0x00, 0xff, b'-', b'9', b'<', b'"', b'\n', b'.'][rng.below(8)],
                2 => u8::try_from(rng.below(256)).expect("byte"),
                _ => {
                    // also clobber a short run, to hit multi-byte counts and lengths
                    let end = (at + 4).min(b.len());
                    for x in &mut b[at..end] {
                        *x = 0xff;
                    }
                    0xff
                }
            };
            b
        })
        .collect()
}

fn write_case(dir: &Path, case: &Case) -> PathBuf {
    for (rel, bytes) in &case.files {
        common::write(dir, rel, bytes);
    }
    dir.join(case.load)
}

/// Loads `path`; panics (failing the test) if it takes longer than the limit. A panic inside
/// `load_asset` propagates and fails the test too.
fn load_quickly(path: &Path, what: &str) {
    let start = Instant::now();
    let result = load_asset(path, &IngestOptions::default());
    let took = start.elapsed();
    assert!(took < TIME_LIMIT, "{what}: took {took:?}");
    if let Err(e) = result {
        assert!(!e.to_string().is_empty(), "{what}: empty error message");
    }
}

fn run(case: &Case, seed: u64) {
    let dir = tempfile::tempdir().expect("tempdir");
    let root = dir.path().join(case.name);
    let path = write_case(&root, case);
    load_asset(&path, &IngestOptions::default())
        .unwrap_or_else(|e| panic!("{}: the undamaged case must load: {e}", case.name));
    let target = root.join(case.target);
    let original = std::fs::read(&target).expect("read target");
    for len in truncation_lengths(original.len()) {
        std::fs::write(&target, &original[..len]).expect("write");
        load_quickly(&path, &format!("{} truncated to {len} bytes", case.name));
    }
    for (i, corrupted) in corruptions(&original, seed).into_iter().enumerate() {
        std::fs::write(&target, corrupted).expect("write");
        load_quickly(&path, &format!("{} corruption #{i}", case.name));
    }
}

#[test]
fn truncated_and_corrupted_inputs_never_panic_or_hang() {
    for (i, case) in cases().iter().enumerate() {
        run(case, 0x5eed + i as u64);
    }
}
