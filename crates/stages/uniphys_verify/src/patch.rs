//! Contact patches: the points of a static part that lie near a moving group, and the threshold
//! search that finds them (reference 12, steps 2 and 4, with thresholds relative to the object).

use uniphys_geometry::{DMat4, DVec3, KdTree};

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
    PosedTree::at_rest(moving).grow_patch(
        static_points,
        start_m,
        step_m,
        max_increments,
        min_points,
    )
}

/// The moving group's kd-tree at rest, queried at a pose of the sweep: the distance from a point
/// to the moved group is the distance from the point taken back to rest (a rigid motion keeps
/// every distance), so no tree is built per pose.
#[derive(Clone, Copy)]
pub(crate) struct PosedTree<'a> {
    rest: &'a KdTree,
    rest_from_object: DMat4,
}

impl<'a> PosedTree<'a> {
    /// The group at rest.
    pub(crate) fn at_rest(rest: &'a KdTree) -> Self {
        Self::new(rest, DMat4::IDENTITY)
    }

    /// The group moved by `object_from_moved` (a rigid motion).
    pub(crate) fn new(rest: &'a KdTree, object_from_moved: DMat4) -> Self {
        Self {
            rest,
            rest_from_object: object_from_moved.inverse(),
        }
    }

    /// Distance from `p` (object frame) to the nearest point of the posed group when it is at
    /// most `max_m` ([`KdTree::nearest_distance_within`]).
    pub(crate) fn nearest_distance_within(&self, p: DVec3, max_m: f64) -> Option<f64> {
        self.rest
            .nearest_distance_within(self.rest_from_object.transform_point3(p), max_m)
    }

    /// [`grow_patch`] against the posed group.
    pub(crate) fn grow_patch(
        &self,
        static_points: &[DVec3],
        start_m: f64,
        step_m: f64,
        max_increments: usize,
        min_points: usize,
    ) -> Option<(Vec<DVec3>, f64)> {
        // Distances once, then thresholds are cheap; a point beyond the last threshold is in
        // no patch, so its distance is not looked for.
        let reach_m = start_m + step_m * max_increments as f64;
        let distances: Vec<f64> = static_points
            .iter()
            .map(|p| {
                self.nearest_distance_within(*p, reach_m)
                    .unwrap_or(f64::INFINITY)
            })
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
    fn spacing_of_a_line_of_points() {
        let points: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(0.0, 0.5 * f64::from(i), 0.0))
            .collect();
        assert!((mean_spacing_m(&points) - 0.5).abs() < 1e-12);
    }
}
