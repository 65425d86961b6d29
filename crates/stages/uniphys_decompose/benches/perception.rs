//! Perception time: `cargo bench -p uniphys_decompose --bench perception`.
//!
//! A cabinet-like object (body, inset lid, front panel, spherical knob; each part finely
//! tessellated) at about 25k and 100k triangles, 8 views at 256 and 512 px. Prints per case the
//! median over runs (release profile, one thread) of the whole 8-view work: rendering (face IDs
//! and shading), built-in segmentation, lifting (with sub-pixel faces) and cross-view consensus,
//! with the regions, merged masks and K prior found (the object has 4 parts; the knob is about
//! 1 % of the visible area, below the prior's 99 % coverage). For contrast, `merged_px_only`:
//! the merged masks when only faces owning a pixel are lifted and the reference rule alone
//! merges them. `floor_ms` reads every pixel of the 8 face-ID images once (the least any
//! per-pixel pass can cost).

use std::time::Instant;

use uniphys_decompose::consensus::{ConsensusOptions, merge_masks, merge_view_masks};
use uniphys_decompose::lift::{LiftOptions, lift_labels, lift_view};
use uniphys_decompose::prior::{K_PRIOR_COVERAGE, k_prior};
use uniphys_decompose::segment::{BuiltinSegmenter, Segmenter, ViewImage};
use uniphys_decompose::views::{ViewOptions, render_views};
use uniphys_geometry::{DVec3, TriMesh};

/// The box `min..max` with every side split into `n x n` quads (12 n^2 triangles).
fn fine_cuboid(min: DVec3, max: DVec3, n: usize) -> TriMesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let size = max - min;
    // Each side: a corner and two edge vectors, ordered for an outward normal.
    let sides = [
        (min, DVec3::Y * size.y, DVec3::X * size.x),
        (
            DVec3::new(min.x, min.y, max.z),
            DVec3::X * size.x,
            DVec3::Y * size.y,
        ),
        (min, DVec3::X * size.x, DVec3::Z * size.z),
        (
            DVec3::new(min.x, max.y, min.z),
            DVec3::Z * size.z,
            DVec3::X * size.x,
        ),
        (min, DVec3::Z * size.z, DVec3::Y * size.y),
        (
            DVec3::new(max.x, min.y, min.z),
            DVec3::Y * size.y,
            DVec3::Z * size.z,
        ),
    ];
    for (corner, u, v) in sides {
        let base = positions.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                positions.push(corner + u * (i as f64 / n as f64) + v * (j as f64 / n as f64));
            }
        }
        let at = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    TriMesh::new(positions, triangles).expect("valid cuboid")
}

/// A UV sphere with `2 * rings * segments` triangles (about).
fn sphere(centre: DVec3, radius_m: f64, rings: usize, segments: usize) -> TriMesh {
    let mut positions = vec![centre + DVec3::Z * radius_m];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = std::f64::consts::TAU * s as f64 / segments as f64;
            positions.push(
                centre
                    + radius_m
                        * DVec3::new(
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            theta.cos(),
                        ),
            );
        }
    }
    positions.push(centre - DVec3::Z * radius_m);
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

/// Body, lid, front panel and knob; `scale` multiplies the tessellation.
fn cabinet(scale: usize) -> TriMesh {
    let body = fine_cuboid(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.9), 38 * scale);
    let lid = fine_cuboid(
        DVec3::new(0.1, 0.1, 0.9),
        DVec3::new(0.9, 0.7, 1.0),
        15 * scale,
    );
    let panel = fine_cuboid(
        DVec3::new(0.15, -0.05, 0.15),
        DVec3::new(0.85, 0.0, 0.75),
        15 * scale,
    );
    let knob = sphere(DVec3::new(0.5, -0.12, 0.45), 0.07, 25 * scale, 50 * scale);
    TriMesh::merge([&body, &lid, &panel, &knob])
}

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

fn main() {
    println!(
        "{:>9} {:>6} {:>10} {:>10} {:>9} {:>9} {:>10} {:>12} {:>8} {:>7} {:>3} {:>14}",
        "triangles",
        "px",
        "render_ms",
        "segment_ms",
        "lift_ms",
        "merge_ms",
        "floor_ms",
        "seg+lift+mrg",
        "regions",
        "merged",
        "K0",
        "merged_px_only"
    );
    for scale in [1usize, 2] {
        let mesh = cabinet(scale);
        let faces = mesh.triangle_count();
        let rgba = vec![[180, 180, 180, 255]; faces];
        let area: Vec<f64> = (0..faces).map(|f| mesh.face_area(f)).collect();
        for resolution_px in [256u32, 512] {
            let options = ViewOptions {
                count: 8,
                resolution_px,
            };
            let mut views = None;
            let render_ms = median_ms(3, || {
                views = Some(render_views(&mesh, &rgba, &options).expect("render"));
            });
            let views = views.expect("rendered");
            let image = |k: usize| ViewImage {
                index: k,
                camera: &views.cameras[k],
                face_ids: &views.face_ids[k],
                colour: &views.colour[k],
                face_material: &[],
            };
            let segmenter = BuiltinSegmenter::default();
            let mut maps = Vec::new();
            let segment_ms = median_ms(5, || {
                maps = (0..8)
                    .map(|k| segmenter.segment(&image(k)).expect("segment"))
                    .collect();
            });
            let mut lifted = Vec::new();
            let lift_ms = median_ms(5, || {
                lifted = (0..8)
                    .map(|k| {
                        lift_view(
                            &mesh,
                            &views.cameras[k],
                            &views.face_ids[k],
                            &maps[k],
                            &area,
                            &LiftOptions::default(),
                        )
                        .expect("lift")
                    })
                    .collect();
            });
            let mut merged = Vec::new();
            let merge_ms = median_ms(5, || {
                merged = merge_view_masks(&lifted, &area, &ConsensusOptions::default());
            });
            // For contrast: pixels only (faces smaller than a pixel left out), plain merge.
            let pixels_only: Vec<_> = (0..8)
                .flat_map(|k| {
                    lift_labels(
                        &views.face_ids[k].face,
                        &maps[k].labels,
                        &area,
                        &LiftOptions::default(),
                    )
                    .expect("lift")
                })
                .collect();
            let merged_pixels_only =
                merge_masks(&pixels_only, &area, &ConsensusOptions::default()).len();
            let floor_ms = median_ms(5, || {
                let covered: usize = views
                    .face_ids
                    .iter()
                    .map(|v| v.face.iter().filter(|&&f| f != 0).count())
                    .sum();
                std::hint::black_box(covered);
            });
            let regions: usize = maps.iter().map(|m| m.region_count()).sum();
            println!(
                "{:>9} {:>6} {:>10.1} {:>10.1} {:>9.1} {:>9.1} {:>10.2} {:>12.1} {:>8} {:>7} {:>3} {:>14}",
                faces,
                resolution_px,
                render_ms,
                segment_ms,
                lift_ms,
                merge_ms,
                floor_ms,
                segment_ms + lift_ms + merge_ms,
                regions,
                merged.len(),
                k_prior(&merged, &area, K_PRIOR_COVERAGE),
                merged_pixels_only
            );
        }
    }
}
