//! Closed solids with outward (counter-clockwise seen from outside) winding, and rigid
//! transforms to place them. Every builder returns a single closed, consistently oriented shell
//! whose vertices are all distinct, so [`TriMesh::is_closed`] holds as built.

use std::f64::consts::TAU;

use uniphys_geometry::{DMat4, DVec3, TriMesh};

/// The axis-aligned box between the corners `min` and `max`.
#[must_use]
pub fn cuboid(min: DVec3, max: DVec3) -> TriMesh {
    TriMesh::cuboid(min, max)
}

/// A box between `min` and `max` hollowed out from the top: a floor and four walls, all `wall`
/// thick, open towards +z. A single closed shell (the rim closes it at the top).
#[must_use]
pub fn open_top_box(min: DVec3, max: DVec3, wall: f64) -> TriMesh {
    let ring = |x0: f64, y0: f64, x1: f64, y1: f64, z: f64| {
        [
            DVec3::new(x0, y0, z),
            DVec3::new(x1, y0, z),
            DVec3::new(x1, y1, z),
            DVec3::new(x0, y1, z),
        ]
    };
    let (ix0, iy0, ix1, iy1) = (min.x + wall, min.y + wall, max.x - wall, max.y - wall);
    let mut positions = Vec::with_capacity(16);
    positions.extend(ring(min.x, min.y, max.x, max.y, min.z)); // 0..4 outer bottom
    positions.extend(ring(min.x, min.y, max.x, max.y, max.z)); // 4..8 outer top
    positions.extend(ring(ix0, iy0, ix1, iy1, max.z)); // 8..12 inner top
    positions.extend(ring(ix0, iy0, ix1, iy1, min.z + wall)); // 12..16 inner floor
    let (ob, ot, it, fl) = (0, 4, 8, 12);
    let mut triangles = vec![
        [ob, ob + 2, ob + 1],
        [ob, ob + 3, ob + 2],
        [fl, fl + 1, fl + 2],
        [fl, fl + 2, fl + 3],
    ];
    for k in 0..4 {
        let n = (k + 1) % 4;
        // Outer wall, rim, inner wall.
        triangles.push([ob + k, ob + n, ot + n]);
        triangles.push([ob + k, ot + n, ot + k]);
        triangles.push([ot + k, ot + n, it + n]);
        triangles.push([ot + k, it + n, it + k]);
        triangles.push([fl + k, it + n, fl + n]);
        triangles.push([fl + k, it + k, it + n]);
    }
    mesh(positions, triangles)
}

/// The solid of revolution of a closed `profile` about the z axis.
///
/// `profile` lists `[radius, z]` points counter-clockwise in the (radius, z) half-plane (radius to
/// the right, z up), at least three of them, radii non-negative; points with radius 0 lie on the
/// axis and become single vertices. The circle is split into `segments` steps, starting on +x.
#[must_use]
pub fn lathe(profile: &[[f64; 2]], segments: u32) -> TriMesh {
    revolve(profile, 0.0, TAU, segments)
}

/// A profile swept about the z axis from angle `start` through `sweep` radians (0 < sweep < 2 pi)
/// in `segments` steps, with flat caps at both ends. The profile follows [`lathe`]'s convention,
/// must stay off the axis and be star-shaped around its centroid (each cap is a fan from it).
#[must_use]
pub fn swept_profile(profile: &[[f64; 2]], start: f64, sweep: f64, segments: u32) -> TriMesh {
    revolve(profile, start, sweep, segments)
}

/// A solid cylinder about the z axis from `z0` to `z1` (`z0 < z1`).
#[must_use]
pub fn cylinder(radius: f64, z0: f64, z1: f64, segments: u32) -> TriMesh {
    lathe(
        &[[0.0, z0], [radius, z0], [radius, z1], [0.0, z1]],
        segments,
    )
}

/// A thick-walled tube (an annulus solid) about the z axis from `z0` to `z1`.
#[must_use]
pub fn tube(inner_radius: f64, outer_radius: f64, z0: f64, z1: f64, segments: u32) -> TriMesh {
    lathe(
        &[
            [inner_radius, z0],
            [outer_radius, z0],
            [outer_radius, z1],
            [inner_radius, z1],
        ],
        segments,
    )
}

/// A segment of a torus about the z axis, centred at the origin: its centre line is the circle of
/// radius `major` in the xy plane from angle `start` through `sweep`, its cross-section a circle of
/// radius `minor` (`minor < major`); both ends are closed by flat caps.
#[must_use]
pub fn torus_segment(
    major: f64,
    minor: f64,
    start: f64,
    sweep: f64,
    major_segments: u32,
    minor_segments: u32,
) -> TriMesh {
    let profile: Vec<[f64; 2]> = (0..minor_segments)
        .map(|k| {
            let a = TAU * f64::from(k) / f64::from(minor_segments);
            [major + minor * a.cos(), minor * a.sin()]
        })
        .collect();
    swept_profile(&profile, start, sweep, major_segments)
}

/// The rigid motion rotating by `angle` radians (right-handed) about the line through `pivot`
/// along `axis` (normalised here).
#[must_use]
pub fn rotation_about(pivot: DVec3, axis: DVec3, angle: f64) -> DMat4 {
    DMat4::from_translation(pivot)
        * DMat4::from_axis_angle(axis.normalize(), angle)
        * DMat4::from_translation(-pivot)
}

/// The exact quarter turn about +x that maps +z to -y and +y to +z: `(x, y, z) -> (x, -z, y)`.
/// Used to turn a shape built opening upwards into one opening to the front (-y).
#[must_use]
pub fn quarter_turn_z_to_front() -> DMat4 {
    DMat4::from_cols_array(&[
        1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, 1.0, 0.0, //
        0.0, -1.0, 0.0, 0.0, //
        0.0, 0.0, 0.0, 1.0,
    ])
}

fn revolve(profile: &[[f64; 2]], start: f64, sweep: f64, segments: u32) -> TriMesh {
    let full = sweep >= TAU;
    let steps = segments.max(3) as usize;
    let stations = if full { steps } else { steps + 1 };
    let angle = |k: usize| start + sweep * k as f64 / steps as f64;
    let mut positions = Vec::new();
    let ids: Vec<Vec<u32>> = profile
        .iter()
        .map(|&[r, z]| {
            if r == 0.0 {
                vec![next_id(&mut positions, DVec3::new(0.0, 0.0, z)); stations]
            } else {
                (0..stations)
                    .map(|k| {
                        let (sin, cos) = angle(k).sin_cos();
                        next_id(&mut positions, DVec3::new(r * cos, r * sin, z))
                    })
                    .collect()
            }
        })
        .collect();
    let at = |j: usize, k: usize| ids[j][k % stations];
    let n = profile.len();
    let mut triangles = Vec::new();
    for j in 0..n {
        let j1 = (j + 1) % n;
        for k in 0..steps {
            let (a, b, c, d) = (at(j, k), at(j, k + 1), at(j1, k + 1), at(j1, k));
            match (a == b, c == d) {
                (true, true) => {}
                (true, false) => triangles.push([a, c, d]),
                (false, true) => triangles.push([a, b, c]),
                (false, false) => {
                    triangles.push([a, b, c]);
                    triangles.push([a, c, d]);
                }
            }
        }
    }
    if !full {
        let centroid = profile
            .iter()
            .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]])
            .map(|s| s / n as f64);
        for (station, flip) in [(0, false), (steps, true)] {
            let (sin, cos) = angle(station).sin_cos();
            let centre = next_id(
                &mut positions,
                DVec3::new(centroid[0] * cos, centroid[0] * sin, centroid[1]),
            );
            for j in 0..n {
                let (p, q) = (at(j, station), at((j + 1) % n, station));
                triangles.push(if flip { [centre, q, p] } else { [centre, p, q] });
            }
        }
    }
    mesh(positions, triangles)
}

/// Appends `p` and returns its index.
fn next_id(positions: &mut Vec<DVec3>, p: DVec3) -> u32 {
    positions.push(p);
    u32::try_from(positions.len() - 1).unwrap_or(u32::MAX)
}

fn mesh(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> TriMesh {
    TriMesh {
        positions,
        triangles,
        ..TriMesh::default()
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    /// Signed enclosed volume: positive when the winding is outward.
    fn volume(m: &TriMesh) -> f64 {
        (0..m.triangle_count())
            .map(|i| {
                let [a, b, c] = m.corners(i);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn polygon_disc_area(radius: f64, segments: u32) -> f64 {
        0.5 * f64::from(segments) * radius * radius * (TAU / f64::from(segments)).sin()
    }

    fn assert_closed_outward(m: &TriMesh, expected_volume: f64) {
        m.validate().unwrap();
        assert!(m.is_closed(), "not closed as built");
        assert!(m.welded(1e-9).is_closed(), "not closed after welding");
        let v = volume(m);
        assert!(
            (v - expected_volume).abs() < 1e-9 * expected_volume.max(1.0) + 1e-12,
            "volume {v}, expected {expected_volume}"
        );
    }

    #[test]
    fn cuboid_is_closed_with_its_exact_volume() {
        assert_closed_outward(&cuboid(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)), 6.0);
    }

    #[test]
    fn open_top_box_is_a_closed_shell_with_wall_volume() {
        let m = open_top_box(DVec3::new(-1.0, -2.0, 0.0), DVec3::new(1.0, 2.0, 3.0), 0.1);
        assert_closed_outward(&m, 2.0 * 4.0 * 3.0 - 1.8 * 3.8 * 2.9);
        assert_eq!(m.bounds().max, DVec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn cylinder_and_tube_are_closed_with_polygon_volumes() {
        let disc = polygon_disc_area(0.5, 32);
        assert_closed_outward(&cylinder(0.5, 1.0, 3.0, 32), disc * 2.0);
        let ring = disc - polygon_disc_area(0.3, 32);
        assert_closed_outward(&tube(0.3, 0.5, 0.0, 2.0, 32), ring * 2.0);
    }

    #[test]
    fn cup_profile_gives_one_closed_shell() {
        let cup = lathe(
            &[
                [0.0, 0.0],
                [1.0, 0.0],
                [1.0, 2.0],
                [0.9, 2.0],
                [0.9, 0.1],
                [0.0, 0.1],
            ],
            24,
        );
        let expected = polygon_disc_area(1.0, 24) * 2.0 - polygon_disc_area(0.9, 24) * 1.9;
        assert_closed_outward(&cup, expected);
    }

    #[test]
    fn half_torus_is_closed_and_capped() {
        let m = torus_segment(1.0, 0.2, -PI / 2.0, PI, 32, 16);
        // Pappus: section area times the path of the centroid, up to tessellation.
        let v = volume(&m);
        let exact = PI * 0.04 * PI;
        assert!(m.is_closed() && m.welded(1e-9).is_closed());
        assert!((v - exact).abs() < 0.03 * exact, "volume {v} vs {exact}");
        let b = m.bounds();
        assert!(b.min.x.abs() < 1e-12 && (b.max.x - 1.2).abs() < 1e-12);
    }

    #[test]
    fn quarter_turn_opens_an_upward_box_to_the_front_and_keeps_it_closed() {
        let m = open_top_box(DVec3::ZERO, DVec3::ONE, 0.1).transformed(&quarter_turn_z_to_front());
        assert!(m.is_closed());
        assert!(volume(&m) > 0.0);
        // The inner floor faced +z; it now faces -y.
        assert!((m.face_normal(2) + DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn rotation_about_keeps_the_pivot_fixed() {
        let pivot = DVec3::new(1.0, 2.0, 3.0);
        let m = rotation_about(pivot, DVec3::X, 1.0);
        assert!((m.transform_point3(pivot) - pivot).length() < 1e-12);
        let p = m.transform_point3(pivot + DVec3::Y);
        assert!((p - pivot - DVec3::new(0.0, 1.0f64.cos(), 1.0f64.sin())).length() < 1e-12);
    }
}
