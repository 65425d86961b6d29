//! Pivots at the centres of a part's rounded ends: a rocker switch's face, a lid's knuckle or a
//! lever's end is an arc about the line it turns on, so the circle through its outline there,
//! seen along the axis, is centred on the hinge.

use uniphys_geometry::{Aabb, DMat3, DVec3, convex_outline, projection_range};

use crate::candidates::{across_axis, distinct_lines};

/// How far from each end of the part's outline (across the axis) the outline is fitted with a
/// circle, as multiples of the part's width the other way: a half for a tight knuckle, a whole
/// width for a rocker's long arc.
const END_REACH_FRACTIONS: [f64; 2] = [0.5, 1.0];
/// Hull edges are cut into pieces at most this share of the outline's larger extent, so a long
/// straight side weighs in a fit as much as an arc drawn with many vertices.
const OUTLINE_STEP_FRACTION: f64 = 0.005;
/// Circle centres farther outside the outline's box than this share of its extent (a flat end
/// fits a huge circle) are no pivots.
const CENTRE_MARGIN_FRACTION: f64 = 0.5;
/// A circle fit whose normal equations have a determinant under this share of their trace
/// cubed is of points on a line.
const SINGULAR_RATIO: f64 = 1e-12;
/// A fit needs at least this many outline points.
const FIT_POINTS_MIN: usize = 5;

/// Pivots of lines along `axis` through the centres of circles fitted to the part's outline
/// across the axis (the convex outline of `part_points` projected along it) near each of its
/// four ends (along the part's box axis of `part_axes` least aligned with the axis, and across
/// both), reaching in by half and by a whole of the part's width; centres far outside the part
/// are left out. Lines closer than 0.5 % of the part's diagonal are given once; each point lies
/// at the middle of the part along the axis. Object frame, metres.
#[must_use]
pub fn rounded_end_pivots(part_points: &[DVec3], axis: DVec3, part_axes: [DVec3; 3]) -> Vec<DVec3> {
    let axis = axis.normalize_or_zero();
    if part_points.len() < 3 || axis == DVec3::ZERO {
        return Vec::new();
    }
    let Some((u, v)) = across_axis(axis, part_axes) else {
        return Vec::new();
    };
    let flat: Vec<[f64; 2]> = part_points.iter().map(|p| [p.dot(u), p.dot(v)]).collect();
    let hull = convex_outline(&flat);
    if hull.len() < 3 {
        return Vec::new();
    }
    let lo = [0, 1].map(|d| hull.iter().map(|q| q[d]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|d| hull.iter().map(|q| q[d]).fold(f64::NEG_INFINITY, f64::max));
    let extent = [hi[0] - lo[0], hi[1] - lo[1]];
    let outline = densify(&hull, OUTLINE_STEP_FRACTION * extent[0].max(extent[1]));
    let middle = {
        let (a, b) = projection_range(part_points, axis);
        0.5 * (a + b)
    };
    let mut out = Vec::new();
    for dim in 0..2 {
        let width = extent[1 - dim];
        for end in [lo[dim], hi[dim]] {
            for reach in END_REACH_FRACTIONS {
                let near: Vec<[f64; 2]> = outline
                    .iter()
                    .copied()
                    .filter(|q| (q[dim] - end).abs() <= reach * width)
                    .collect();
                let Some(centre) = fit_circle(&near) else {
                    continue;
                };
                let inside = (0..2).all(|d| {
                    let margin = CENTRE_MARGIN_FRACTION * extent[d];
                    centre[d] >= lo[d] - margin && centre[d] <= hi[d] + margin
                });
                if inside {
                    out.push(axis * middle + u * centre[0] + v * centre[1]);
                }
            }
        }
    }
    let diagonal = Aabb::from_points(part_points).diagonal();
    distinct_lines(&out, axis, 5e-3 * diagonal)
}

/// Points along a closed polygon's edges, at most `step` apart (its vertices included).
fn densify(polygon: &[[f64; 2]], step: f64) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        let pieces = if step > 0.0 {
            (length / step).ceil().max(1.0) as usize
        } else {
            1
        };
        for k in 0..pieces {
            let t = k as f64 / pieces as f64;
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
}

/// Centre of the circle through `points` by least squares on `x² + y² = 2 a x + 2 b y + c`
/// (Kåsa's fit); `None` for fewer than [`FIT_POINTS_MIN`] points or points on a line.
fn fit_circle(points: &[[f64; 2]]) -> Option<[f64; 2]> {
    if points.len() < FIT_POINTS_MIN {
        return None;
    }
    // Centred for conditioning.
    let n = points.len() as f64;
    let mean = [
        points.iter().map(|q| q[0]).sum::<f64>() / n,
        points.iter().map(|q| q[1]).sum::<f64>() / n,
    ];
    let mut normal = DMat3::ZERO;
    let mut rhs = DVec3::ZERO;
    for q in points {
        let (x, y) = (q[0] - mean[0], q[1] - mean[1]);
        let row = DVec3::new(2.0 * x, 2.0 * y, 1.0);
        normal += DMat3::from_cols(row * row.x, row * row.y, row * row.z);
        rhs += row * (x * x + y * y);
    }
    // Points on a line leave the system singular: its determinant vanishes against its scale.
    let scale = normal.x_axis.x + normal.y_axis.y + normal.z_axis.z;
    if normal.determinant().abs() <= SINGULAR_RATIO * scale.powi(3) {
        return None;
    }
    let s = normal.inverse() * rhs;
    (s.x.is_finite() && s.y.is_finite()).then(|| [s.x + mean[0], s.y + mean[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_is_fitted_through_its_arc_and_a_line_has_no_centre() {
        let arc: Vec<[f64; 2]> = (0..20)
            .map(|k| {
                let t = 0.1 * f64::from(k);
                [0.3 + 2.0 * t.cos(), -0.1 + 2.0 * t.sin()]
            })
            .collect();
        let c = fit_circle(&arc).expect("a centre");
        assert!(
            (c[0] - 0.3).abs() < 1e-9 && (c[1] + 0.1).abs() < 1e-9,
            "{c:?}"
        );
        let line: Vec<[f64; 2]> = (0..10)
            .map(|k| [f64::from(k), 2.0 * f64::from(k)])
            .collect();
        assert!(fit_circle(&line).is_none());
    }

    #[test]
    fn a_lever_is_pivoted_at_the_centre_of_its_round_end() {
        // A lever 0.01 m thick along z, 0.04 m wide (y), its square end at x = 0.2 and its
        // other end a half disc of radius 0.02 m about its pin, the line x = 0, y = 0.
        let mut points = Vec::new();
        for z in [0.0, 0.01] {
            for i in 0..=40 {
                let t = std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(i) / 40.0;
                points.push(DVec3::new(0.02 * t.cos(), 0.02 * t.sin(), z));
            }
            for i in 0..=100 {
                let x = 0.002 * f64::from(i);
                points.extend([DVec3::new(x, -0.02, z), DVec3::new(x, 0.02, z)]);
            }
            for i in 0..=20 {
                points.push(DVec3::new(0.2, -0.02 + 0.002 * f64::from(i), z));
            }
        }
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let pivots = rounded_end_pivots(&points, DVec3::Z, axes);
        let nearest = pivots
            .iter()
            .map(|p| p.truncate().length())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-3, "the lever's pin is missed by {nearest} m");
        // Each point lies at the middle of the lever's thickness.
        assert!(
            pivots.iter().all(|p| (p.z - 0.005).abs() < 1e-9),
            "{pivots:?}"
        );
    }
}
