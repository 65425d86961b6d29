//! Writes sample LVLM views and a face-ID render of a small cabinet to a directory, for looking
//! at: `cargo run -p uniphys_render --example lvlm_views -- OUT_DIR`.

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_render::{
    PartScene, RenderResult, ViewOptions, axis_candidate_views, encode_png, orbit_cameras,
    part_composite, pivot_candidate_views, render_face_ids, shade,
};

fn main() -> RenderResult<()> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".to_owned()));
    let meshes = vec![
        TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.6, 0.4, 0.8)),
        TriMesh::cuboid(DVec3::new(0.05, -0.03, 0.05), DVec3::new(0.55, 0.0, 0.75)),
        TriMesh::cuboid(DVec3::new(0.45, -0.08, 0.35), DVec3::new(0.5, -0.03, 0.45)),
        TriMesh::cuboid(DVec3::new(0.2, 0.1, 0.3), DVec3::new(0.4, 0.3, 0.5)),
    ];
    let colours = [
        [90, 140, 200, 255],
        [220, 40, 40, 255],
        [240, 200, 40, 255],
        [60, 170, 80, 255],
    ];
    let scene = PartScene {
        part_meshes: &meshes,
        part_rgba: &colours,
    };
    let options = ViewOptions::default();
    let write = |name: &str, bytes: Vec<u8>| {
        std::fs::write(out.join(name), bytes).map_err(|e| {
            uniphys_render::RenderError::UnsupportedPng(format!("writing {name}: {e}"))
        })
    };
    for part in 0..meshes.len() {
        write(
            &format!("part_{}.png", part + 1),
            encode_png(&part_composite(&scene, part, &options))?,
        )?;
    }
    let n = DVec3::new(0.0, -1.0, 0.0);
    let mut axes = [DVec3::X, DVec3::Y, DVec3::Z, n, n, n, n, n, n, n];
    axes[0] = n;
    for (m, axis) in axes[1..7].iter_mut().enumerate() {
        let a = m as f64 * std::f64::consts::PI / 6.0;
        *axis = DVec3::new(a.cos(), 0.0, a.sin());
    }
    axes[7] = DVec3::X;
    axes[8] = DVec3::Y;
    axes[9] = DVec3::Z;
    let origin = DVec3::new(0.55, -0.015, 0.4);
    for (v, img) in axis_candidate_views(&scene, 1, &axes, origin, &options)
        .iter()
        .enumerate()
    {
        write(&format!("axes_{v}.png"), encode_png(img)?)?;
    }
    let pivots = [
        origin,
        DVec3::new(0.55, -0.015, 0.1),
        DVec3::new(0.55, -0.015, 0.7),
        DVec3::new(0.05, -0.015, 0.1),
        DVec3::new(0.05, -0.015, 0.7),
        DVec3::new(0.3, -0.015, 0.4),
    ];
    for (v, img) in pivot_candidate_views(&scene, 1, &pivots, &options)
        .iter()
        .enumerate()
    {
        write(&format!("pivots_{v}.png"), encode_png(img)?)?;
    }
    let all = TriMesh::merge(&meshes);
    let cam = orbit_cameras(&all.bounds(), 8, 256, 256)[0];
    let ids = render_face_ids(&all, &cam);
    let palette = |f: usize| {
        let h = (f as u32).wrapping_mul(2_654_435_761);
        [(h >> 24) as u8, (h >> 16) as u8, (h >> 8) as u8, 255]
    };
    write(
        "face_ids_view0.png",
        encode_png(&shade(&ids, &cam, &palette))?,
    )?;
    Ok(())
}
