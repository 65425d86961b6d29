//! `--emit DIR`: the inputs of `bench/verification.py` and our times on them.
//!
//! Layout: `DIR/<asset>/part_<i>.obj` (object frame, metres), `DIR/<asset>/<joint>_moving.npy`
//! and `_parent.npy` (float64, N x 3: the moving group's samples the kd-tree is built over and
//! the parent's samples that are queried, exactly those of the sweep's contact search at rest),
//! and `DIR/ours.json` with our median times and results:
//! - per part: `solid_mass_properties(mesh, 128)` (exact for a closed mesh, else voxels) and
//!   `voxelize(mesh, 128)` alone, with the voxel volume both as we count it (surface voxels
//!   half full) and as trimesh counts it (every filled voxel whole);
//! - per movable joint: `KdTree::new(moving)` plus `grow_patch(parent, ..)` with the sweep's
//!   parameters at rest (start and step in metres, increments, minimum points), its point
//!   count and threshold.

use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::Path;

use uniphys_geometry::{DVec3, KdTree, TriMesh, solid_mass_properties, voxelize};
use uniphys_verify::{SweepParams, grow_patch, moving_group};

use crate::fixture::Fixture;
use crate::median_ms;

/// Voxels across the longest side (the reference's `pitch = max(extents) / 128`).
const RESOLUTION: usize = 128;
/// Runs of each volume computation.
const VOLUME_RUNS: usize = 5;
/// Runs of each contact search (about a millisecond each).
const CONTACT_RUNS: usize = 21;

/// Writes meshes, point sets and `ours.json` under `dir`.
pub(crate) fn write(dir: &Path, fixtures: &[Fixture], params: &SweepParams) -> io::Result<()> {
    let mut parts = Vec::new();
    let mut joints = Vec::new();
    for f in fixtures {
        let asset_dir = dir.join(f.name);
        fs::create_dir_all(&asset_dir)?;
        for (i, mesh) in f.meshes.iter().enumerate() {
            let file = format!("{}/part_{i}.obj", f.name);
            fs::write(dir.join(&file), obj_text(mesh))?;
            parts.push(part_entry(&file, &f.part_names[i], mesh));
        }
        for joint in f.joints.iter().filter(|j| j.kind.is_movable()) {
            let moving = moving_group(&f.joints, joint.child);
            let moving_points = f.scene.points_of(&moving);
            let parent_points = f.scene.points_of(&[joint.parent.0 as usize]);
            let stem = format!("{}/{}", f.name, joint.name);
            fs::write(dir.join(format!("{stem}_moving.npy")), npy(&moving_points))?;
            fs::write(dir.join(format!("{stem}_parent.npy")), npy(&parent_points))?;
            let patch = &params.patch;
            let start_m = patch.start_fraction * f.scene.diagonal_m;
            let step_m = patch.step_fraction * f.scene.diagonal_m;
            let increments = patch.initial_increments();
            let (ms, found) = median_ms(CONTACT_RUNS, || {
                let tree = KdTree::new(moving_points.clone());
                grow_patch(
                    &parent_points,
                    &tree,
                    start_m,
                    step_m,
                    increments,
                    patch.min_points,
                )
            });
            let (points, threshold_m) = found.map_or((0, f64::NAN), |(p, t)| (p.len(), t));
            joints.push(format!(
                "{{\"asset\": {}, \"joint\": {}, \"moving\": {}, \"parent\": {}, \
                 \"start_m\": {start_m:e}, \"step_m\": {step_m:e}, \"increments\": {increments}, \
                 \"min_points\": {}, \"ours_ms\": {ms:e}, \"points\": {points}, \
                 \"threshold_m\": {}}}",
                json_str(f.name),
                json_str(&joint.name),
                json_str(&format!("{stem}_moving.npy")),
                json_str(&format!("{stem}_parent.npy")),
                patch.min_points,
                json_num(threshold_m),
            ));
        }
    }
    let text = format!(
        "{{\"resolution\": {RESOLUTION}, \"volume_runs\": {VOLUME_RUNS}, \"contact_runs\": \
         {CONTACT_RUNS},\n\"parts\": [\n{}\n],\n\"joints\": [\n{}\n]}}\n",
        parts.join(",\n"),
        joints.join(",\n")
    );
    fs::write(dir.join("ours.json"), text)
}

/// Our volume computations on one part, as a JSON object.
fn part_entry(file: &str, name: &str, mesh: &TriMesh) -> String {
    let (solid_ms, solid) = median_ms(VOLUME_RUNS, || solid_mass_properties(mesh, RESOLUTION));
    let (solid_m3, method) = solid.map_or((f64::NAN, "error".to_owned()), |(m, method)| {
        (m.volume_m3, method.as_str())
    });
    let (voxel_ms, grid) = median_ms(VOLUME_RUNS, || voxelize(mesh, RESOLUTION));
    let grid = grid.expect("the example parts voxelise");
    let whole_m3 = grid.filled_count() as f64 * grid.pitch_m.powi(3);
    format!(
        "{{\"obj\": {}, \"name\": {}, \"triangles\": {}, \
         \"solid_ms\": {solid_ms:e}, \"solid_method\": {}, \"solid_m3\": {}, \
         \"voxelize_ms\": {voxel_ms:e}, \"voxel_m3\": {:e}, \"voxel_whole_m3\": {whole_m3:e}, \
         \"filled_count\": {}, \"pitch_m\": {:e}}}",
        json_str(file),
        json_str(name),
        mesh.triangle_count(),
        json_str(&method),
        json_num(solid_m3),
        grid.volume_m3(),
        grid.filled_count(),
        grid.pitch_m,
    )
}

/// Wavefront OBJ of the mesh (vertices at full precision, 1-based triangles).
fn obj_text(mesh: &TriMesh) -> String {
    let mut out = String::new();
    for p in &mesh.positions {
        writeln!(out, "v {:e} {:e} {:e}", p.x, p.y, p.z).expect("write to a string");
    }
    for t in &mesh.triangles {
        writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).expect("write to a string");
    }
    out
}

/// A NumPy `.npy` (format 1.0) of the points as a little-endian float64 N x 3 array.
fn npy(points: &[DVec3]) -> Vec<u8> {
    let mut header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, 3), }}",
        points.len()
    );
    // Magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64
    // and ended by a newline.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(
        &u16::try_from(header.len())
            .expect("short header")
            .to_le_bytes(),
    );
    out.extend_from_slice(header.as_bytes());
    for p in points {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// A JSON string literal (the names here are plain ASCII; quotes and backslashes escaped).
fn json_str(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// A JSON number, `null` when not finite.
fn json_num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".to_owned()
    }
}
