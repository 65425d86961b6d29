//! Face-ID rendering against analytic projections of simple scenes.

use uniphys_geometry::{Aabb, DVec3, TriMesh};
use uniphys_render::{
    Camera, DEFAULT_FOV_Y_RAD, REFERENCE_RIG_DIRECTIONS, camera_from_direction, decode_png,
    encode_png, orbit_cameras, render_face_ids, render_face_ids_into, shade,
};

fn unit_cube() -> TriMesh {
    TriMesh::cuboid(DVec3::splat(-0.5), DVec3::splat(0.5))
}

/// Triangles of `TriMesh::cuboid` per face, in its order -z, +z, -y, +y, -x, +x.
fn cuboid_face_of_triangle(t: usize) -> DVec3 {
    [
        DVec3::NEG_Z,
        DVec3::Z,
        DVec3::NEG_Y,
        DVec3::Y,
        DVec3::NEG_X,
        DVec3::X,
    ][t / 2]
}

#[test]
fn a_cube_seen_along_each_axis_shows_only_the_faces_turned_to_the_camera() {
    let cube = unit_cube();
    for axis in [
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ] {
        let up = if axis.z.abs() > 0.5 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let cam = Camera::look_at(axis * 5.0, DVec3::ZERO, up, DEFAULT_FOV_Y_RAD, 48, 40);
        let img = render_face_ids(&cube, &cam);
        let mut seen = [0usize; 12];
        for y in 0..img.height_px {
            for x in 0..img.width_px {
                if let Some(f) = img.face_at(x, y) {
                    seen[f] += 1;
                    let n = img.normal_world[(y * img.width_px + x) as usize];
                    assert_eq!(n, [axis.x as f32, axis.y as f32, axis.z as f32]);
                }
            }
        }
        for (t, &count) in seen.iter().enumerate() {
            let facing = cuboid_face_of_triangle(t) == axis;
            assert_eq!(
                count > 0,
                facing,
                "axis {axis}: triangle {t} seen {count} times"
            );
        }
        // The face is a 1 m square at 4.5 m: its projected area in pixels.
        let focal_px = 20.0 / (0.5 * DEFAULT_FOV_Y_RAD).tan();
        let side_px = focal_px / 4.5;
        let covered = img.covered_pixels() as f64;
        assert!(
            (covered - side_px * side_px).abs() < 4.0 * side_px,
            "{covered} vs {}",
            side_px * side_px
        );
    }
}

#[test]
fn face_ids_at_known_pixels_of_a_known_projection() {
    // A 2 m square at z = 0 split along its diagonal, seen from 4 m above; X to the right, Y up.
    let quad = TriMesh::new(
        vec![
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .expect("valid");
    let cam = Camera::look_at(
        DVec3::new(0.0, 0.0, 4.0),
        DVec3::ZERO,
        DVec3::Y,
        0.9,
        81,
        61,
    );
    let img = render_face_ids(&quad, &cam);
    let focal_px = 30.5 / 0.45_f64.tan();
    // World (x, y, 0) appears at (40.5 + f x / 4, 30.5 - f y / 4).
    let pixel = |x: f64, y: f64| {
        (
            (40.5 + focal_px * x / 4.0) as u32,
            (30.5 - focal_px * y / 4.0) as u32,
        )
    };
    let (x, y) = pixel(0.5, -0.5); // below the diagonal: triangle 0
    assert_eq!(img.face_at(x, y), Some(0));
    let (x, y) = pixel(-0.5, 0.5); // above it: triangle 1
    assert_eq!(img.face_at(x, y), Some(1));
    let (x, y) = pixel(0.9, 0.5);
    assert_eq!(img.face_at(x, y), Some(0));
    let (x, y) = pixel(1.2, 0.0); // outside the square
    assert_eq!(img.face_at(x, y), None);
    assert_eq!(img.face_at(0, 0), None);
    assert_eq!(img.face_at(81, 0), None, "outside the image");
    // The square spans f * 2 / 4 pixels each way.
    let side_px = focal_px * 0.5;
    let covered = img.covered_pixels() as f64;
    assert!(
        (covered - side_px * side_px).abs() < 4.0 * side_px,
        "{covered}"
    );
    // Seen from below it is the same square (both sides are drawn), mirrored.
    let below = Camera::look_at(
        DVec3::new(0.0, 0.0, -4.0),
        DVec3::ZERO,
        DVec3::Y,
        0.9,
        81,
        61,
    );
    let img_below = render_face_ids(&quad, &below);
    assert_eq!(img_below.covered_pixels(), img.covered_pixels());
    assert_eq!(img_below.normal_world[30 * 81 + 40], [0.0, 0.0, -1.0]);
}

#[test]
fn depth_is_the_analytic_view_depth_on_flat_and_tilted_surfaces() {
    let cube = unit_cube();
    let cam = Camera::look_at(
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::ZERO,
        DVec3::Z,
        DEFAULT_FOV_Y_RAD,
        33,
        33,
    );
    let img = render_face_ids(&cube, &cam);
    let d = img.depth_at(16, 16).expect("centre covered");
    assert!((f64::from(d) - 2.5).abs() < 1e-6, "{d}");
    assert_eq!(img.depth_m[0], f32::INFINITY);
    // A plane tilted against the view: x + 0.5 y + 0.25 z = 0, one big triangle.
    let n = DVec3::new(1.0, 0.5, 0.25);
    let big = 20.0;
    let on_plane = |y: f64, z: f64| DVec3::new(-(0.5 * y + 0.25 * z), y, z);
    let tri = TriMesh::new(
        vec![
            on_plane(-big, -big),
            on_plane(big, -big),
            on_plane(0.0, big),
        ],
        vec![[0, 1, 2]],
    )
    .expect("valid");
    let cam = Camera::look_at(
        DVec3::new(4.0, 0.3, 0.2),
        DVec3::ZERO,
        DVec3::Z,
        0.8,
        40,
        30,
    );
    let img = render_face_ids(&tri, &cam);
    assert_eq!(img.covered_pixels(), 40 * 30);
    let forward = (cam.target_m - cam.eye_m).normalize();
    for (x, y) in [(0u32, 0u32), (39, 29), (20, 15), (5, 25), (33, 2)] {
        let depth = f64::from(img.depth_at(x, y).expect("covered"));
        // Ray through the pixel centre: a point at view depth 1 on it, then hit the plane.
        let on_ray = cam.unproject(f64::from(x) + 0.5, f64::from(y) + 0.5, 1.0);
        let dir = on_ray - cam.eye_m;
        let t = -n.dot(cam.eye_m) / n.dot(dir);
        let expected = t * dir.dot(forward);
        assert!(
            (depth - expected).abs() < 1e-5 * expected,
            "({x}, {y}): {depth} vs {expected}"
        );
    }
}

#[test]
fn a_small_box_in_front_hides_the_big_box_whatever_the_triangle_order() {
    let big = TriMesh::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0));
    let small = TriMesh::cuboid(DVec3::new(1.5, -0.2, -0.2), DVec3::new(2.0, 0.2, 0.2));
    let cam = Camera::look_at(
        DVec3::new(6.0, 0.0, 0.0),
        DVec3::ZERO,
        DVec3::Z,
        DEFAULT_FOV_Y_RAD,
        65,
        65,
    );
    for small_first in [false, true] {
        let mesh = if small_first {
            TriMesh::merge([&small, &big])
        } else {
            TriMesh::merge([&big, &small])
        };
        let small_range = if small_first { 0..12 } else { 12..24 };
        let img = render_face_ids(&mesh, &cam);
        let centre = img.face_at(32, 32).expect("covered");
        assert!(small_range.contains(&centre), "centre shows {centre}");
        assert!((f64::from(img.depth_at(32, 32).expect("covered")) - 4.0).abs() < 1e-6);
        let side = img
            .face_at(32, 20)
            .expect("big box visible around the small one");
        assert!(!small_range.contains(&side), "edge shows {side}");
        assert!((f64::from(img.depth_at(32, 20).expect("covered")) - 5.0).abs() < 1e-6);
    }
}

#[test]
fn a_finely_tessellated_plane_has_no_cracks() {
    // 16 x 16 cells of 2 triangles each, many pixel centres on or next to shared edges.
    let n = 16usize;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(DVec3::new(
                i as f64 / n as f64 * 4.0 - 2.0,
                j as f64 / n as f64 * 4.0 - 2.0,
                0.0,
            ));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let v = |a: usize, b: usize| ((j + b) * (n + 1) + i + a) as u32;
            triangles.push([v(0, 0), v(1, 0), v(1, 1)]);
            triangles.push([v(0, 0), v(1, 1), v(0, 1)]);
        }
    }
    let plane = TriMesh::new(positions, triangles).expect("valid");
    let cam = Camera::look_at(
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::ZERO,
        DVec3::Y,
        1.2,
        64,
        48,
    );
    let img = render_face_ids(&plane, &cam);
    assert_eq!(img.covered_pixels(), 64 * 48);
}

#[test]
fn triangles_crossing_the_near_plane_are_clipped_when_the_eye_is_inside_a_box() {
    let room = TriMesh::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0));
    // A wide field of view: the side walls, which extend behind the eye, are in view.
    let cam = Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 2.0, 40, 40);
    let img = render_face_ids(&room, &cam);
    assert_eq!(img.covered_pixels(), 40 * 40);
    let mut walls = std::collections::BTreeSet::new();
    for (k, &id) in img.face.iter().enumerate() {
        walls.insert((id as usize - 1) / 2);
        assert!(
            img.depth_m[k] > 0.0 && img.depth_m[k] <= 1.0 + 1e-6,
            "{}",
            img.depth_m[k]
        );
    }
    // +x ahead, and the four side walls; never -x behind the eye.
    assert_eq!(walls.into_iter().collect::<Vec<_>>(), vec![0, 1, 2, 3, 5]);
    let ahead = img.face_at(20, 20).expect("covered");
    assert_eq!(ahead / 2, 5);
}

#[test]
fn the_eight_view_rig_matches_the_reference_and_frames_the_box() {
    let bounds = Aabb {
        min: DVec3::new(0.2, -1.0, 0.0),
        max: DVec3::new(2.2, 0.0, 0.5),
    };
    for (w, h) in [(64, 64), (80, 40), (30, 90)] {
        let cams = orbit_cameras(&bounds, 8, w, h);
        assert_eq!(cams.len(), 8);
        for (cam, d) in cams.iter().zip(REFERENCE_RIG_DIRECTIONS) {
            let expected = DVec3::from_array(d).normalize();
            let got = (cam.eye_m - cam.target_m).normalize();
            assert!(got.distance(expected) < 1e-12, "{got} vs {expected}");
            assert!(cam.target_m.distance(bounds.center()) < 1e-12);
            assert_corners_inside(&bounds, cam);
        }
    }
    let cams = orbit_cameras(&bounds, 5, 50, 50);
    assert_eq!(cams.len(), 5);
    for (i, a) in cams.iter().enumerate() {
        assert_corners_inside(&bounds, a);
        for b in &cams[i + 1..] {
            let (da, db) = (
                (a.eye_m - a.target_m).normalize(),
                (b.eye_m - b.target_m).normalize(),
            );
            assert!(da.dot(db) < 0.9, "views too close: {da} {db}");
        }
    }
    // Straight down the up axis still works.
    let top = camera_from_direction(&bounds, DVec3::Z, 32, 32);
    assert_corners_inside(&bounds, &top);
}

fn assert_corners_inside(bounds: &Aabb, cam: &Camera) {
    for i in 0..8 {
        let c = DVec3::new(
            if i & 1 == 0 {
                bounds.min.x
            } else {
                bounds.max.x
            },
            if i & 2 == 0 {
                bounds.min.y
            } else {
                bounds.max.y
            },
            if i & 4 == 0 {
                bounds.min.z
            } else {
                bounds.max.z
            },
        );
        let p = cam.project(c).expect("in front");
        assert!(
            p.x_px >= 0.0
                && p.x_px <= f64::from(cam.width_px)
                && p.y_px >= 0.0
                && p.y_px <= f64::from(cam.height_px),
            "corner {c} at {p:?} outside {}x{}",
            cam.width_px,
            cam.height_px
        );
    }
}

#[test]
fn rendering_is_deterministic_and_the_png_round_trips() {
    let mesh = TriMesh::merge([
        &TriMesh::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0)),
        &TriMesh::cuboid(DVec3::new(0.5, 0.5, 0.5), DVec3::new(1.5, 1.2, 1.7)),
    ]);
    let cams = orbit_cameras(&mesh.bounds(), 8, 48, 36);
    let palette = |f: usize| [(f * 37 % 256) as u8, (f * 91 % 256) as u8, 200, 255];
    // Reused buffers start from another size and another scene.
    let mut reused = render_face_ids(
        &TriMesh::cuboid(DVec3::ZERO, DVec3::ONE),
        &orbit_cameras(&mesh.bounds(), 8, 70, 20)[3],
    );
    for cam in &cams {
        let a = render_face_ids(&mesh, cam);
        let b = render_face_ids(&mesh, cam);
        assert_eq!(a, b);
        render_face_ids_into(&mesh, cam, &mut reused);
        assert_eq!(reused, a);
        assert!(a.covered_pixels() > 100);
        let png_a = encode_png(&shade(&a, cam, &palette)).expect("encodes");
        let png_b = encode_png(&shade(&b, cam, &palette)).expect("encodes");
        assert_eq!(png_a, png_b);
        let shaded = shade(&a, cam, &palette);
        let decoded = decode_png(&png_a).expect("decodes");
        assert_eq!(decoded, shaded);
        // Background stays transparent, covered pixels are opaque and darker than the base colour.
        for (k, &id) in a.face.iter().enumerate() {
            let p = shaded.pixels[k];
            if id == 0 {
                assert_eq!(p, [0, 0, 0, 0]);
            } else {
                assert_eq!(p[3], 255);
                assert!(p[2] <= 200 && p[2] >= 60, "{p:?}");
            }
        }
    }
}

#[test]
fn on_equal_depth_the_smaller_triangle_index_wins() {
    // Triangles 0 and 2 coincide with 1 and 3; 1 and 3 come later and must never show.
    let positions = vec![
        DVec3::new(-1.0, -1.0, 0.0),
        DVec3::new(1.0, -1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(-1.0, 1.0, 0.0),
    ];
    let mesh =
        TriMesh::new(positions, vec![[0, 1, 2], [0, 1, 2], [0, 2, 3], [0, 2, 3]]).expect("valid");
    let cam = Camera::look_at(
        DVec3::new(0.3, -0.2, 3.0),
        DVec3::ZERO,
        DVec3::Y,
        1.0,
        50,
        40,
    );
    let img = render_face_ids(&mesh, &cam);
    let mut seen = [0usize; 4];
    for y in 0..40 {
        for x in 0..50 {
            if let Some(f) = img.face_at(x, y) {
                seen[f] += 1;
            }
        }
    }
    assert!(seen[0] > 100 && seen[2] > 100, "{seen:?}");
    assert_eq!((seen[1], seen[3]), (0, 0), "{seen:?}");
}
