//! Contact patches: the points of a static part that lie near a moving group, and the threshold
//! search that finds them (reference 12, steps 2 and 4, with thresholds relative to the object).

use uniphys_geometry::{DMat3, DQuat, DVec3, KdTree, symmetric_eigen};

/// How contact thresholds are searched, as fractions of the object diagonal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchParams {
    /// First threshold.
    pub start_fraction: f64,
    /// Threshold increment.
    pub step_fraction: f64,
    /// Points a patch needs (the reference asks for more than 6).
    pub min_points: usize,
    /// Largest threshold searched for the initial patch.
    pub max_initial_fraction: f64,
    /// Increments allowed above the initial threshold at each sweep step before the step counts
    /// as contact lost (reference: 5 increments of 0.01 mesh units).
    pub max_step_increments: usize,
}

impl Default for PatchParams {
    /// Start at and grow by 0.5 % of the diagonal, at least 7 points, initial search up to 10 %
    /// of the diagonal, 5 increments per step.
    fn default() -> Self {
        Self {
            start_fraction: 0.005,
            step_fraction: 0.005,
            min_points: 7,
            max_initial_fraction: 0.1,
            max_step_increments: 5,
        }
    }
}

impl PatchParams {
    /// Increments the initial patch search may take: from `start_fraction` up to
    /// `max_initial_fraction` in steps of `step_fraction` (rounded up).
    #[must_use]
    pub fn initial_increments(&self) -> usize {
        ((self.max_initial_fraction - self.start_fraction) / self.step_fraction)
            .ceil()
            .max(0.0) as usize
    }
}

/// Grows the threshold from `start_m` by `step_m` until the patch has `min_points` points or
/// `max_increments` increments were made. Returns the patch and the threshold, or `None`.
///
/// `moving` is a kd-tree over the moving group's points; a point of `static_points` belongs to
/// the patch when its nearest moving point is within the threshold (`<=`). Public so that the
/// verification benchmark can time exactly the contact search the sweep runs.
pub fn grow_patch(
    static_points: &[DVec3],
    moving: &KdTree,
    start_m: f64,
    step_m: f64,
    max_increments: usize,
    min_points: usize,
) -> Option<(Vec<DVec3>, f64)> {
    // Distances once, then thresholds are cheap.
    let distances: Vec<f64> = static_points
        .iter()
        .map(|p| moving.nearest_distance(*p))
        .collect();
    for k in 0..=max_increments {
        let threshold = start_m + step_m * k as f64;
        let count = distances.iter().filter(|&&d| d <= threshold).count();
        if count >= min_points {
            let patch = static_points
                .iter()
                .zip(&distances)
                .filter(|&(_, &d)| d <= threshold)
                .map(|(p, _)| *p)
                .collect();
            return Some((patch, threshold));
        }
    }
    None
}

/// Mean distance from each point to its nearest other point (0 for fewer than two points).
pub(crate) fn mean_spacing_m(points: &[DVec3]) -> f64 {
    if points.len() < 2 {
        return 0.0;
    }
    let total: f64 = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| p.distance_squared(*q))
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        })
        .sum();
    total / points.len() as f64
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
/// normal, the in-plane rotation (searched in 0.5 degree steps over a quarter turn) with the
/// smallest bounding rectangle; the box of smallest volume wins. Unlike the principal axes this
/// finds the edges of square slabs (a square door), whose in-plane principal axes are arbitrary.
/// Returns `[normal, first edge, second edge]`, unit and orthogonal.
#[must_use]
pub fn box_axes(points: &[DVec3]) -> [DVec3; 3] {
    let principal = principal_axes(points);
    if points.len() < 3 {
        return principal;
    }
    let extent = |d: DVec3| {
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let x = p.dot(d);
                (lo.min(x), hi.max(x))
            });
        hi - lo
    };
    let mut best: Option<(f64, [DVec3; 3])> = None;
    for normal in principal {
        let start = normal.any_orthonormal_vector();
        let depth = extent(normal);
        for step in 0..180 {
            let turn =
                DQuat::from_axis_angle(normal, f64::from(step) * std::f64::consts::PI / 360.0);
            let u = turn * start;
            let v = normal.cross(u);
            let volume = depth.max(1e-12) * extent(u) * extent(v);
            if best
                .as_ref()
                .is_none_or(|(b, _)| volume < *b * (1.0 - 1e-9))
            {
                best = Some((volume, [normal, u, v]));
            }
        }
    }
    best.map_or(principal, |(_, axes)| axes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patch_grows_until_enough_points() {
        let moving = KdTree::new(vec![DVec3::ZERO]);
        let statics: Vec<DVec3> = (1..=10).map(|i| DVec3::X * (0.1 * f64::from(i))).collect();
        // Points at 0.1 .. 1.0: 3 points need a threshold of 0.3 (start 0.1, step 0.1, 2 steps).
        let (patch, threshold) = grow_patch(&statics, &moving, 0.1, 0.1, 5, 3).expect("found");
        assert_eq!(patch.len(), 3);
        assert!((threshold - 0.3).abs() < 1e-12);
        assert!(grow_patch(&statics, &moving, 0.1, 0.1, 1, 3).is_none());
    }

    #[test]
    fn spacing_and_principal_axes_of_a_line_of_points() {
        let points: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(0.0, 0.5 * f64::from(i), 0.0))
            .collect();
        assert!((mean_spacing_m(&points) - 0.5).abs() < 1e-12);
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
}
