//! `uniphys measure`: mass properties of every part of a mesh file, exact and voxelised, as JSON.
//! A debugging aid and the hook the benchmarks and the trimesh cross-check use.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use serde_json::{Value, json};
use uniphys_geometry::{MassProperties, VoxelGrid};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::UpAxis;

fn mass_json(m: &MassProperties) -> Value {
    json!({ "volume_m3": m.volume_m3, "com_m": m.com.to_array(), "inertia_per_density": m.inertia_about_com_per_density.to_cols_array_2d() })
}

pub(crate) fn measure(mesh: &Path, voxel_resolution: usize) -> anyhow::Result<ExitCode> {
    // Measure in the file's own coordinates so results compare with other tools reading the file.
    let options = IngestOptions {
        up_axis: Some(UpAxis::Z),
        ..IngestOptions::default()
    };
    let loaded = load_asset(mesh, &options)?;
    let mut parts = Vec::new();
    for part in &loaded.asset.parts {
        let start = Instant::now();
        let exact = MassProperties::from_closed_mesh(&part.mesh);
        let exact_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let grid = VoxelGrid::voxelize(&part.mesh, voxel_resolution)?;
        let voxel = grid.mass_properties();
        let voxel_ms = start.elapsed().as_secs_f64() * 1e3;
        parts.push(json!({
            "name": part.name,
            "triangles": part.mesh.triangle_count(),
            "closed": exact.is_some(),
            "exact": exact.as_ref().map(mass_json),
            "voxel": mass_json(&voxel),
            "voxel_pitch_m": grid.pitch_m,
            "exact_ms": exact_ms,
            "voxel_ms": voxel_ms,
        }));
    }
    println!(
        "{}",
        json!({ "file": mesh, "voxel_resolution": voxel_resolution, "parts": parts })
    );
    Ok(ExitCode::SUCCESS)
}
