//! Face-ID rendering time: `cargo bench -p uniphys_render --bench face_ids`.
//!
//! Prints one row per case: triangles, resolution, median milliseconds per view over the 8 views
//! of the reference rig (release profile, one thread; fresh images with `render_face_ids`, and
//! reused buffers with `render_face_ids_into`), and the ratio to the baselines measured in the
//! same run:
//! - the floor: allocating and filling the output buffers of one 512x512 view (no triangles);
//! - the naive renderer on a small case: for every pixel, test every triangle.

use std::time::Instant;

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_render::{Camera, FaceIdImage, orbit_cameras, render_face_ids, render_face_ids_into};

/// A closed UV sphere of radius 1 m with about `2 * rings * segments` triangles, slightly
/// squashed and bumped so views differ.
fn sphere(rings: usize, segments: usize) -> TriMesh {
    let mut positions = vec![DVec3::new(0.0, 0.0, 1.0)];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = std::f64::consts::TAU * s as f64 / segments as f64;
            let bump = 1.0 + 0.05 * (5.0 * phi).sin() * (3.0 * theta).sin();
            positions.push(DVec3::new(
                1.2 * bump * theta.sin() * phi.cos(),
                bump * theta.sin() * phi.sin(),
                0.8 * bump * theta.cos(),
            ));
        }
    }
    positions.push(DVec3::new(0.0, 0.0, -0.8));
    let ring = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let bottom = (positions.len() - 1) as u32;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, ring(1, s), ring(1, s + 1)]);
        triangles.push([bottom, ring(rings - 1, s + 1), ring(rings - 1, s)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            triangles.push([ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)]);
            triangles.push([ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)]);
        }
    }
    TriMesh::new(positions, triangles).expect("valid sphere")
}

/// Median of `runs` timings of `f` in milliseconds.
fn median_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Median time per view over the 8 rig views: fresh images, and one image's buffers reused.
fn per_view_ms(mesh: &TriMesh, size_px: u32, runs: usize) -> (f64, f64, usize) {
    let cams = orbit_cameras(&mesh.bounds(), 8, size_px, size_px);
    let mut covered = 0;
    let fresh = median_ms(runs, || {
        for cam in &cams {
            covered = std::hint::black_box(render_face_ids(mesh, cam)).covered_pixels();
        }
    }) / cams.len() as f64;
    let mut image = render_face_ids(mesh, &cams[0]);
    let reused = median_ms(runs, || {
        for cam in &cams {
            render_face_ids_into(mesh, cam, &mut image);
            std::hint::black_box(&image);
        }
    }) / cams.len() as f64;
    (fresh, reused, covered)
}

/// The floor: one view's buffers allocated, cleared and converted, no triangles.
fn floor_ms(size_px: u32) -> f64 {
    let n = (size_px * size_px) as usize;
    median_ms(15, || {
        let inv_depth = vec![0.0f64; n];
        let face = vec![0u32; n];
        let depth: Vec<f32> = inv_depth
            .iter()
            .map(|&d| {
                if d > 0.0 {
                    (1.0 / d) as f32
                } else {
                    f32::INFINITY
                }
            })
            .collect();
        let normals = vec![[0.0f32; 3]; n];
        std::hint::black_box((face, depth, normals));
    })
}

/// Naive reference: every pixel tests every triangle (ray-triangle, nearest wins).
fn naive(mesh: &TriMesh, cam: &Camera) -> Vec<u32> {
    let (w, h) = (cam.width_px, cam.height_px);
    let mut out = vec![0u32; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let through = cam.unproject(f64::from(x) + 0.5, f64::from(y) + 0.5, 1.0);
            let dir = through - cam.eye_m;
            let mut best = (f64::INFINITY, 0u32);
            for (i, _) in mesh.triangles.iter().enumerate() {
                let [a, b, c] = mesh.corners(i);
                // Moller-Trumbore, both sides.
                let (e1, e2) = (b - a, c - a);
                let p = dir.cross(e2);
                let det = e1.dot(p);
                if det.abs() < 1e-15 {
                    continue;
                }
                let t0 = cam.eye_m - a;
                let u = t0.dot(p) / det;
                let q = t0.cross(e1);
                let v = dir.dot(q) / det;
                let t = e2.dot(q) / det;
                if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 && t < best.0 {
                    best = (t, i as u32 + 1);
                }
            }
            out[(y * w + x) as usize] = best.1;
        }
    }
    out
}

fn agreement(a: &FaceIdImage, b: &[u32]) -> f64 {
    let same = a.face.iter().zip(b).filter(|(x, y)| x == y).count();
    same as f64 / b.len() as f64
}

fn main() {
    let floor = floor_ms(512);
    println!("floor: 512x512 buffers, no triangles: {floor:.3} ms");

    // Naive baseline on a small case.
    let small = sphere(16, 32);
    let cam = orbit_cameras(&small.bounds(), 8, 64, 64)[0];
    let naive_ms = median_ms(3, || {
        std::hint::black_box(naive(&small, &cam));
    });
    let ours_small_ms = median_ms(15, || {
        std::hint::black_box(render_face_ids(&small, &cam));
    });
    let agree = agreement(&render_face_ids(&small, &cam), &naive(&small, &cam));
    println!(
        "naive per-pixel x per-triangle, {} triangles, 64x64: {naive_ms:.2} ms; ours {ours_small_ms:.3} ms ({:.0}x faster), same face id on {:.2} % of pixels",
        small.triangle_count(),
        naive_ms / ours_small_ms,
        100.0 * agree
    );
    println!();
    println!(
        "| triangles | resolution | ms per view | x floor | ms per view, buffers reused | x floor | covered px |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    // (2, 2000): 4000 long slivers from the poles to the equator, the worst case of a box scan.
    for (rings, segments) in [(2, 2000), (50, 100), (158, 316), (224, 448)] {
        let mesh = sphere(rings, segments);
        for size in [256u32, 512, 800] {
            let (fresh, reused, covered) = per_view_ms(&mesh, size, 7);
            println!(
                "| {} | {size}x{size} | {fresh:.2} | {:.1} | {reused:.2} | {:.1} | {covered} |",
                mesh.triangle_count(),
                fresh / floor,
                reused / floor
            );
        }
    }
}
