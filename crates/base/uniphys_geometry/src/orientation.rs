//! Orientation of a point set: principal axes and the edges of a tight box.

use glam::{DMat3, DQuat, DVec3};

use crate::symmetric_eigen;

/// Smallest and largest of `p . d` over the points (`(inf, -inf)` for none).
#[must_use]
pub fn projection_range(points: &[DVec3], d: DVec3) -> (f64, f64) {
    points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let x = p.dot(d);
            (lo.min(x), hi.max(x))
        })
}

/// Length of the points' projection on a unit direction `d` (0 for none).
#[must_use]
pub fn extent_along(points: &[DVec3], d: DVec3) -> f64 {
    let (lo, hi) = projection_range(points, d);
    (hi - lo).max(0.0)
}

/// Principal directions of a point set: unit eigenvectors of the covariance, largest spread
/// first. Falls back to the coordinate axes for fewer than two points.
#[must_use]
pub fn principal_axes(points: &[DVec3]) -> [DVec3; 3] {
    if points.len() < 2 {
        return [DVec3::X, DVec3::Y, DVec3::Z];
    }
    let mean = points.iter().sum::<DVec3>() / points.len() as f64;
    let mut cov = DMat3::ZERO;
    for p in points {
        let d = *p - mean;
        cov += DMat3::from_cols(d * d.x, d * d.y, d * d.z);
    }
    let (_, vectors) = symmetric_eigen(cov / points.len() as f64);
    [vectors.z_axis, vectors.y_axis, vectors.x_axis]
}

/// Edge directions of a tight box around the points: for each principal axis taken as the box's
/// normal, the in-plane rotation with the smallest bounding rectangle (0.5 degree steps over a
/// half turn from the next principal axis, then refined by ternary search); the box of smallest
/// volume wins. Then the same search about each edge of the box found, while the box shrinks (a
/// few rounds): a part whose principal axes lean (a table whose drawer or legs are not
/// symmetric) gets the box of its faces, not one tilted a few degrees with its principal axis.
/// Unlike the principal axes this finds the edges of square slabs (a square door), whose
/// in-plane principal axes are arbitrary. Returns `[normal, first edge, second edge]`, unit and
/// orthogonal.
#[must_use]
pub fn box_axes(points: &[DVec3]) -> [DVec3; 3] {
    let principal = principal_axes(points);
    if points.len() < 3 {
        return principal;
    }
    // A box's extents along any direction are those of the points' convex hull: searching over
    // the hull's corners finds the same box at a fraction of the cost (flat sets keep all).
    let corners = crate::convex_hull(points).map(|hull| hull.positions);
    let points = corners.as_deref().unwrap_or(points);
    let first = tightest_about(points, principal);
    let mut best = first;
    for _ in 0..BOX_REFINE_ROUNDS {
        let next = tightest_about(points, best.1);
        if next.0 >= best.0 * (1.0 - 1e-9) {
            break;
        }
        best = next;
    }
    // In the order and with the signs of the first box's edges when it turned less than 30
    // degrees (each edge then has one nearest), so that refining a box that barely moves does
    // not reorder what its axes are used for.
    let nearest = first.1.map(|a| {
        best.1
            .into_iter()
            .map(|b| if b.dot(a) < 0.0 { -b } else { b })
            .max_by(|x, y| x.dot(a).total_cmp(&y.dot(a)))
            .filter(|b| b.dot(a) > (std::f64::consts::PI / 6.0).cos())
    });
    match nearest {
        [Some(a), Some(b), Some(c)] => [a, b, c],
        _ => best.1,
    }
}

/// Rounds of [`box_axes`]' search about the edges of the box found so far.
const BOX_REFINE_ROUNDS: usize = 3;

/// The smallest box (its volume and axes) turned about one of `normals`, each in its plane.
fn tightest_about(points: &[DVec3], normals: [DVec3; 3]) -> (f64, [DVec3; 3]) {
    let extent = |d: DVec3| {
        let (lo, hi) = projection_range(points, d);
        hi - lo
    };
    let mut best: Option<(f64, [DVec3; 3])> = None;
    for (k, normal) in normals.into_iter().enumerate() {
        // Start at the next axis: the box of `normals` itself is found at angle 0 exactly.
        let start = normals[(k + 1) % 3];
        let depth = extent(normal).max(1e-12);
        let frame = |angle: f64| {
            let u = DQuat::from_axis_angle(normal, angle) * start;
            let v = normal.cross(u);
            (depth * extent(u) * extent(v), [normal, u, v])
        };
        let step = std::f64::consts::PI / 360.0;
        let coarse = (0..180)
            .map(|i| f64::from(i) * step)
            .min_by(|a, b| frame(*a).0.total_cmp(&frame(*b).0))
            .unwrap_or(0.0);
        // Refine within one coarse step on each side (the area is unimodal there).
        let (mut lo, mut hi) = (coarse - step, coarse + step);
        for _ in 0..40 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if frame(m1).0 <= frame(m2).0 {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        for angle in [coarse, 0.5 * (lo + hi)] {
            let (volume, axes) = frame(angle);
            if best
                .as_ref()
                .is_none_or(|(b, _)| volume < *b * (1.0 - 1e-12))
            {
                best = Some((volume, axes));
            }
        }
    }
    best.unwrap_or((f64::INFINITY, normals))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn principal_axes_of_a_line_of_points() {
        let points: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(0.0, 0.5 * f64::from(i), 0.0))
            .collect();
        let axes = principal_axes(&points);
        assert!((axes[0].abs() - DVec3::Y).length() < 1e-9, "{:?}", axes[0]);
    }

    #[test]
    fn box_axes_find_the_edges_of_a_square_slab_turned_by_20_degrees() {
        // Corners and edge points of a 1 x 1 x 0.02 slab turned 20 degrees about z: its in-plane
        // principal axes are arbitrary, its box edges are not.
        let turn = DQuat::from_rotation_z(20f64.to_radians());
        let mut points = Vec::new();
        for i in 0..=10 {
            for j in 0..=10 {
                for z in [0.0, 0.02] {
                    points.push(turn * DVec3::new(f64::from(i) * 0.1, f64::from(j) * 0.1, z));
                }
            }
        }
        let [normal, u, v] = box_axes(&points);
        assert!((normal.abs() - DVec3::Z).length() < 1e-6, "{normal}");
        let edge = turn * DVec3::X;
        let best = u.dot(edge).abs().max(v.dot(edge).abs());
        assert!(best > (0.5f64).to_radians().cos(), "{u} {v} vs {edge}");
    }

    #[test]
    fn box_axes_of_a_table_with_one_leg_follow_its_faces_not_its_leaning_principal_axes() {
        // A 1 x 0.6 top over a single leg at one corner: the points' principal axes lean
        // toward the leg, the box of the faces does not.
        let mut points = Vec::new();
        for i in 0..=20 {
            for j in 0..=12 {
                for z in [0.70, 0.75] {
                    points.push(DVec3::new(f64::from(i) * 0.05, f64::from(j) * 0.05, z));
                }
            }
        }
        for k in 0..=140 {
            let z = f64::from(k) * 0.005;
            for (x, y) in [(0.0, 0.0), (0.05, 0.0), (0.0, 0.05), (0.05, 0.05)] {
                points.push(DVec3::new(x, y, z));
            }
        }
        let lean = principal_axes(&points)
            .iter()
            .map(|a| a.dot(DVec3::Z).abs())
            .fold(0.0, f64::max);
        assert!(lean < 1f64.to_radians().cos(), "principal axes lean {lean}");
        for axis in box_axes(&points) {
            let aligned = [DVec3::X, DVec3::Y, DVec3::Z]
                .iter()
                .map(|e| axis.dot(*e).abs())
                .fold(0.0, f64::max);
            assert!(aligned > 0.1f64.to_radians().cos(), "{axis}");
        }
    }
}
