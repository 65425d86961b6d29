//! Articulation candidates of a moving part from its contact with its parent (reference 7.2 and
//! 17 item 13): 10 unit axes and 6 pivots.

use uniphys_geometry::{
    DQuat, DVec3, KdTree, fit_plane_ransac, kmeans, principal_axes, projection_range,
};

use crate::patch::{PatchParams, grow_patch};
use crate::{VerifyError, VerifyResult};

/// Number of candidate axes.
pub const AXIS_CANDIDATES: usize = 10;
/// Number of candidate pivots.
pub const PIVOT_CANDIDATES: usize = 6;

/// Candidate axes and pivots of one moving part.
#[derive(Debug, Clone, PartialEq)]
pub struct ArticulationCandidates {
    /// Points of the parent near the moving group, object frame, metres.
    pub contact_points: Vec<DVec3>,
    /// Unit normal of the plane fitted to the contact points.
    pub contact_normal: DVec3,
    /// Ten unit axes: the contact normal, six in-plane directions 30 degrees apart starting at
    /// the contact's principal direction, then the three `frame_axes` given.
    pub axes: Vec<DVec3>,
    /// Six pivots: five k-means centres of the contact points, then their centroid.
    pub pivots: Vec<DVec3>,
}

/// Candidates for a moving group (points `moving_points`) attached to a parent (points
/// `parent_points`). `frame_axes` are the last three axis candidates: the world axes in the
/// reference; the moving part's principal axes make the candidates independent of the pose.
/// Deterministic for a given `seed`.
///
/// Errors: fewer than 3 contact points within 10 % of the diagonal.
pub fn articulation_candidates(
    moving_points: &[DVec3],
    parent_points: &[DVec3],
    frame_axes: [DVec3; 3],
    diagonal_m: f64,
    params: &PatchParams,
    seed: u64,
) -> VerifyResult<ArticulationCandidates> {
    let tree = KdTree::new(moving_points.to_vec());
    let start = params.start_fraction * diagonal_m;
    let step = params.step_fraction * diagonal_m;
    let (patch, _) = grow_patch(
        parent_points,
        &tree,
        start,
        step,
        params.initial_increments(),
        params.min_points.max(3),
    )
    .ok_or_else(|| {
        VerifyError::InvalidParameter(format!(
            "the part does not touch its parent: fewer than {} contact points within {:.3} m",
            params.min_points.max(3),
            params.max_initial_fraction * diagonal_m
        ))
    })?;
    let tolerance = 0.01 * diagonal_m;
    let (plane, _) = fit_plane_ransac(&patch, tolerance, 200, seed)?;
    let normal = plane.normal.normalize();
    let principal = principal_axes(&patch)
        .into_iter()
        .map(|a| a.reject_from_normalized(normal))
        .find(|a| a.length() > 1e-6)
        .unwrap_or_else(|| normal.any_orthonormal_vector())
        .normalize();
    let mut axes = vec![normal];
    for k in 0..6 {
        let turn = DQuat::from_axis_angle(normal, f64::from(k) * std::f64::consts::PI / 6.0);
        axes.push((turn * principal).normalize());
    }
    axes.extend(frame_axes.iter().map(|a| a.normalize()));
    let clusters = kmeans(&patch, 5, seed, 100)?;
    let mut pivots = clusters.centres;
    // Fewer distinct points than 5: repeat the first centre so the list keeps its length.
    while pivots.len() < PIVOT_CANDIDATES - 1 {
        pivots.push(pivots[0]);
    }
    pivots.push(patch.iter().sum::<DVec3>() / patch.len() as f64);
    Ok(ArticulationCandidates {
        contact_points: patch,
        contact_normal: normal,
        axes,
        pivots,
    })
}

/// Pivots on the lines where hinges and spin axes of a part lie: for each of the part's box
/// axes `axes`, the lines along it through the box's edges, the middles of its faces and its
/// centre (a door's hinge edge, a screen's bottom edge, a handle's ends, a knob's centre line),
/// each given by its point at the middle of the box; the part's mean point (on the axis of a
/// part symmetric about it); then, for each of the 12 edge lines, the point of the parent
/// (`parent_points`) nearest to it along the part's extent (a hinge often sits on the corner of
/// the opening its panel closes, just off the panel's own edge). 40 points for 3 axes and a
/// parent; object frame, metres.
#[must_use]
pub fn edge_pivots(part_points: &[DVec3], parent_points: &[DVec3], axes: [DVec3; 3]) -> Vec<DVec3> {
    if part_points.is_empty() {
        return Vec::new();
    }
    let ranges = axes.map(|a| projection_range(part_points, a));
    let mut out = Vec::with_capacity(40);
    let mut edges = Vec::with_capacity(12);
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let along = 0.5 * (ranges[k].0 + ranges[k].1);
        for (i, at_u) in spread(ranges[u]).into_iter().enumerate() {
            for (j, at_v) in spread(ranges[v]).into_iter().enumerate() {
                let p = axes[k] * along + axes[u] * at_u + axes[v] * at_v;
                out.push(p);
                if i != 1 && j != 1 {
                    edges.push((k, p));
                }
            }
        }
    }
    out.push(part_points.iter().sum::<DVec3>() / part_points.len() as f64);
    for (k, p) in edges {
        let axis = axes[k];
        let nearest = parent_points
            .iter()
            .filter(|q| {
                let t = q.dot(axis);
                t >= ranges[k].0 && t <= ranges[k].1
            })
            .min_by(|a, b| {
                let d = |q: &DVec3| (*q - p).reject_from_normalized(axis).length_squared();
                d(a).total_cmp(&d(b))
            });
        if let Some(q) = nearest {
            // Moved along the axis to the middle of the part, like the others.
            out.push(*q + axis * (p - *q).dot(axis));
        }
    }
    out
}

/// Widths of the bands at a part's sides whose material gives [`band_pivots`], fractions of the
/// part's width across the axis: a thin band finds the edge's own cross-section (a door's panel
/// beside its hinge, without the handle that widens the part's box), a wide one a recessed or
/// rounded edge.
const BAND_FRACTIONS: [f64; 2] = [0.05, 0.2];

/// Pivots of lines along `axis` where a hinge may run inside a part's edge: across the axis (along
/// the part's box axis, of `part_axes`, least aligned with it, and the direction across both),
/// the part's points (`part_points`) in a band at each of its four sides (see `BAND_FRACTIONS`) span a
/// rectangle; its corners, side middles and centre give a line each; so do the points of the
/// part's whole cross-section at quarters of its width and depth. Real hinges seldom lie on
/// the part's box edge: a door's box grows with its handle and frame, and its hinge sits inside
/// the panel's own thickness. Lines closer than 0.5 % of the part's diagonal are given once;
/// each point lies at the middle of the part along the axis. Object frame, metres.
#[must_use]
pub fn band_pivots(part_points: &[DVec3], axis: DVec3, part_axes: [DVec3; 3]) -> Vec<DVec3> {
    let axis = axis.normalize_or_zero();
    if part_points.is_empty() || axis == DVec3::ZERO {
        return Vec::new();
    }
    let Some((u, v)) = across_axis(axis, part_axes) else {
        return Vec::new();
    };
    let (lo_t, hi_t) = projection_range(part_points, axis);
    let middle = 0.5 * (lo_t + hi_t);
    let flat: Vec<[f64; 2]> = part_points.iter().map(|p| [p.dot(u), p.dot(v)]).collect();
    let ranges = [
        projection_range(part_points, u),
        projection_range(part_points, v),
    ];
    let diagonal = uniphys_geometry::Aabb::from_points(part_points).diagonal();
    let mut out: Vec<DVec3> = Vec::new();
    for fraction in BAND_FRACTIONS {
        for dim in 0..2 {
            let (lo, hi) = ranges[dim];
            let width = fraction * (hi - lo);
            for at_low in [true, false] {
                let band = flat.iter().filter(|q| {
                    if at_low {
                        q[dim] <= lo + width
                    } else {
                        q[dim] >= hi - width
                    }
                });
                let Some((b_lo, b_hi)) = band.fold(None, |acc: Option<([f64; 2], [f64; 2])>, q| {
                    Some(acc.map_or((*q, *q), |(l, h)| {
                        (
                            [l[0].min(q[0]), l[1].min(q[1])],
                            [h[0].max(q[0]), h[1].max(q[1])],
                        )
                    }))
                }) else {
                    continue;
                };
                for x in spread((b_lo[0], b_hi[0])) {
                    for y in spread((b_lo[1], b_hi[1])) {
                        out.push(axis * middle + u * x + v * y);
                    }
                }
            }
        }
    }
    // The whole cross-section at quarters: a rocker's or a blade's pivot sits inside the part,
    // between its edges and its middle.
    for fu in QUARTERS {
        for fv in QUARTERS {
            let at = |(lo, hi): (f64, f64), f: f64| lo + f * (hi - lo);
            out.push(axis * middle + u * at(ranges[0], fu) + v * at(ranges[1], fv));
        }
    }
    distinct_lines(&out, axis, 5e-3 * diagonal)
}

/// Two unit directions across unit `axis`: `u` along the box axis of `part_axes` least aligned
/// with it (the first such), and `v = axis × u`; `None` when every box axis lies along it.
pub(crate) fn across_axis(axis: DVec3, part_axes: [DVec3; 3]) -> Option<(DVec3, DVec3)> {
    let u = part_axes
        .iter()
        .map(|a| a.reject_from_normalized(axis))
        .filter(|a| a.length() > 1e-6)
        .reduce(|best, a| if a.length() > best.length() { a } else { best })?
        .normalize();
    Some((u, axis.cross(u)))
}

/// Fractions of a part's cross-section across an axis where [`band_pivots`] also put lines.
const QUARTERS: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];

/// The first of `pivots` on each distinct line along `axis`: a pivot within `min_apart_m` of a
/// line already kept is on it.
pub(crate) fn distinct_lines(pivots: &[DVec3], axis: DVec3, min_apart_m: f64) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::new();
    for p in pivots {
        if out
            .iter()
            .all(|q| (*p - *q).reject_from_normalized(axis).length() > min_apart_m)
        {
            out.push(*p);
        }
    }
    out
}

/// The two ends and the middle of a range.
fn spread((lo, hi): (f64, f64)) -> [f64; 3] {
    [lo, 0.5 * (lo + hi), hi]
}

#[cfg(test)]
mod tests {
    use super::*;
    use uniphys_geometry::TriMesh;

    fn grid(z: f64, n: usize, step: f64) -> Vec<DVec3> {
        (0..n)
            .flat_map(|i| {
                (0..n).map(move |j| DVec3::new(i as f64 * step, j as f64 * step * 0.5, z))
            })
            .collect()
    }

    #[test]
    fn a_lid_on_a_box_gives_a_vertical_normal_and_in_plane_axes() {
        let lid = grid(0.01, 20, 0.05);
        let top = grid(0.0, 20, 0.05);
        let c = articulation_candidates(
            &lid,
            &top,
            [DVec3::X, DVec3::Y, DVec3::Z],
            1.5,
            &PatchParams::default(),
            1,
        )
        .expect("candidates");
        assert_eq!(c.axes.len(), AXIS_CANDIDATES);
        assert_eq!(c.pivots.len(), PIVOT_CANDIDATES);
        assert!((c.contact_normal.abs() - DVec3::Z).length() < 1e-9);
        for a in &c.axes {
            assert!((a.length() - 1.0).abs() < 1e-12);
        }
        for a in &c.axes[1..7] {
            assert!(a.dot(DVec3::Z).abs() < 1e-9);
        }
        // The contact spreads most along x (0.95 m against 0.475 m), so the first in-plane axis is x.
        assert!(
            (c.axes[1].abs() - DVec3::X).length() < 1e-6,
            "{:?}",
            c.axes[1]
        );
        assert!(
            (c.axes[4].abs() - DVec3::Y).length() < 1e-6,
            "{:?}",
            c.axes[4]
        );
        let centroid = top.iter().sum::<DVec3>() / top.len() as f64;
        assert!((c.pivots[5] - centroid).length() < 1e-12);
    }

    #[test]
    fn edge_pivots_lie_on_every_edge_line_of_a_box() {
        // A door 1 m wide (x), 0.05 m thick (y), 2 m tall (z): its hinge runs along a vertical
        // edge, e.g. the line x = 0, y = 0.
        let door = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.05, 2.0));
        let points = uniphys_geometry::sample_points(&door, 2000, 3);
        // A frame post beside the hinge edge, 1 cm off the door (x = -0.01).
        let post: Vec<DVec3> = (0..=20)
            .map(|i| DVec3::new(-0.01, 0.0, 0.1 * f64::from(i)))
            .collect();
        let pivots = edge_pivots(&points, &post, [DVec3::X, DVec3::Y, DVec3::Z]);
        // 28 on the door; the post lies beside the 8 edge lines along z and y, not along x.
        assert_eq!(pivots.len(), 36);
        let to_line =
            |p: DVec3, on: DVec3, axis: DVec3| (p - on).reject_from_normalized(axis).length();
        for (on, axis) in [
            (DVec3::ZERO, DVec3::Z),
            (DVec3::new(1.0, 0.05, 0.0), DVec3::Z),
            (DVec3::new(0.5, 0.025, 0.0), DVec3::Z),
            (DVec3::new(0.0, 0.0, 2.0), DVec3::X),
            (DVec3::new(-0.01, 0.0, 0.0), DVec3::Z),
        ] {
            let nearest = pivots
                .iter()
                .map(|p| to_line(*p, on, axis))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-3, "{on} {axis}: {nearest}");
        }
    }

    #[test]
    fn band_pivots_find_a_hinge_inside_a_door_widened_by_its_handle() {
        // A door panel 1 m wide (x), 0.04 m thick (y from 0 to 0.04), 2 m tall (z), with a
        // handle bar standing 0.1 m proud of its front near the far edge (x = 0.9). The hinge
        // runs up the panel's near edge, in the middle of its thickness: x = 0, y = 0.02.
        let panel = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.04, 2.0));
        let handle = TriMesh::cuboid(DVec3::new(0.88, 0.04, 0.8), DVec3::new(0.92, 0.14, 1.2));
        let mut points = uniphys_geometry::sample_points(&panel, 4000, 3);
        points.extend(uniphys_geometry::sample_points(&handle, 500, 4));
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let hinge = DVec3::new(0.0, 0.02, 0.0);
        let to_hinge = |p: &DVec3| (*p - hinge).reject_from_normalized(DVec3::Z).length();
        let nearest = band_pivots(&points, DVec3::Z, axes)
            .iter()
            .map(to_hinge)
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 0.005, "band pivots miss the hinge by {nearest}");
        // The box's edge lines, 0.07 m apart across the box the handle grew to 0.14 m, miss it
        // by the panel's half thickness.
        let box_nearest = edge_pivots(&points, &[], axes)
            .iter()
            .map(to_hinge)
            .fold(f64::INFINITY, f64::min);
        assert!(box_nearest > 0.015, "{box_nearest}");
    }

    #[test]
    fn parts_that_do_not_touch_have_no_candidates() {
        let far = grid(1.0, 5, 0.05);
        let top = grid(0.0, 5, 0.05);
        let err = articulation_candidates(
            &far,
            &top,
            [DVec3::X, DVec3::Y, DVec3::Z],
            1.0,
            &PatchParams::default(),
            1,
        );
        assert!(err.is_err());
    }
}
