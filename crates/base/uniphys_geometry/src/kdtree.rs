use glam::DVec3;

use crate::Aabb;

/// Ranges at most this long are scanned linearly.
const LEAF_SIZE: usize = 8;

/// A static kd-tree over points for nearest-neighbour distance queries (exact, Euclidean).
///
/// Implicit layout: the points are reordered so that in every range `[lo, hi)` longer than a
/// leaf, the median `mid = (lo + hi) / 2` splits the range along `axes[mid]` (the axis of
/// largest spread), smaller coordinates left.
pub struct KdTree {
    points: Vec<DVec3>,
    axes: Vec<u8>,
    bounds: Aabb,
}

impl KdTree {
    /// Builds the tree in O(n log n).
    #[must_use]
    pub fn new(mut points: Vec<DVec3>) -> Self {
        let mut axes = vec![0u8; points.len()];
        build(&mut points, &mut axes);
        let bounds = Aabb::from_points(&points);
        Self {
            points,
            axes,
            bounds,
        }
    }

    /// Number of points in the tree.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the tree holds no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Distance from `q` to the nearest point; infinite for an empty tree.
    #[must_use]
    pub fn nearest_distance(&self, q: DVec3) -> f64 {
        let mut best = f64::INFINITY;
        self.search(q, 0, self.points.len(), &mut best);
        best.sqrt()
    }

    /// Distance from `q` to the nearest point when it is at most `max_m`, else `None`: the same
    /// distance [`Self::nearest_distance`] gives, found without visiting the parts of the tree
    /// farther than `max_m` (a query far from every point costs one box test).
    #[must_use]
    pub fn nearest_distance_within(&self, q: DVec3, max_m: f64) -> Option<f64> {
        if self.points.is_empty() || max_m.is_nan() || max_m < 0.0 {
            return None;
        }
        // A bound a hair above the reach, so that rounding never drops a point at max_m.
        let bound_sq = max_m * max_m * (1.0 + 1e-9) + f64::MIN_POSITIVE;
        let outside = (self.bounds.min - q)
            .max(q - self.bounds.max)
            .max(DVec3::ZERO);
        if outside.length_squared() > bound_sq {
            return None;
        }
        let mut best = bound_sq;
        self.search(q, 0, self.points.len(), &mut best);
        let distance = best.sqrt();
        (distance <= max_m).then_some(distance)
    }

    fn search(&self, q: DVec3, lo: usize, hi: usize, best: &mut f64) {
        if hi - lo <= LEAF_SIZE {
            for p in &self.points[lo..hi] {
                *best = best.min(p.distance_squared(q));
            }
            return;
        }
        let mid = (lo + hi) / 2;
        let split = self.points[mid];
        *best = best.min(split.distance_squared(q));
        let axis = usize::from(self.axes[mid]);
        let diff = q[axis] - split[axis];
        let (near, far) = if diff < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.search(q, near.0, near.1, best);
        if diff * diff < *best {
            self.search(q, far.0, far.1, best);
        }
    }
}

/// Arranges `points` into the implicit tree, recording split axes at the same positions.
fn build(points: &mut [DVec3], axes: &mut [u8]) {
    if points.len() <= LEAF_SIZE {
        return;
    }
    let (min, max) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let spread = max - min;
    let axis = if spread.x >= spread.y && spread.x >= spread.z {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    };
    let mid = points.len() / 2;
    points.select_nth_unstable_by(mid, |a, b| a[axis].total_cmp(&b[axis]));
    axes[mid] = axis as u8;
    let (left, rest) = points.split_at_mut(mid);
    let (left_axes, rest_axes) = axes.split_at_mut(mid);
    build(left, left_axes);
    build(&mut rest[1..], &mut rest_axes[1..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SplitMix64;

    #[test]
    fn nearest_distance_matches_brute_force() {
        let mut rng = SplitMix64::new(11);
        let mut random = || DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64() * 0.1);
        let points: Vec<DVec3> = (0..500).map(|_| random()).collect();
        let queries: Vec<DVec3> = (0..200).map(|_| random() * 1.5 - 0.25).collect();
        let tree = KdTree::new(points.clone());
        for q in queries {
            let brute = points
                .iter()
                .map(|p| p.distance(q))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(tree.nearest_distance(q), brute);
        }
    }

    #[test]
    fn bounded_queries_agree_with_the_unbounded_one_within_their_reach() {
        let mut rng = SplitMix64::new(12);
        let mut random = || DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
        let tree = KdTree::new((0..400).map(|_| random()).collect());
        for _ in 0..300 {
            let q = random() * 2.0 - DVec3::splat(0.5);
            let exact = tree.nearest_distance(q);
            for reach in [0.0, 0.01, 0.05, 0.2, 1.0] {
                let expected = (exact <= reach).then_some(exact);
                assert_eq!(tree.nearest_distance_within(q, reach), expected);
            }
            // A point exactly at the reach is within it.
            assert_eq!(tree.nearest_distance_within(q, exact), Some(exact));
        }
        assert_eq!(
            KdTree::new(Vec::new()).nearest_distance_within(DVec3::ZERO, 1.0),
            None
        );
    }

    #[test]
    fn hand_checked_small_cases() {
        assert_eq!(
            KdTree::new(Vec::new()).nearest_distance(DVec3::ZERO),
            f64::INFINITY
        );
        // Points on the x axis at 0..20; the query (7.25, 3, 4) is nearest to x = 7: 5.0052.
        let tree = KdTree::new(
            (0..20)
                .map(|i| DVec3::new(f64::from(i), 0.0, 0.0))
                .collect(),
        );
        let d = tree.nearest_distance(DVec3::new(7.25, 3.0, 4.0));
        assert!((d - (0.0625f64 + 25.0).sqrt()).abs() < 1e-15);
        // Duplicates are fine.
        let tree = KdTree::new(vec![DVec3::ONE; 30]);
        assert_eq!(tree.nearest_distance(DVec3::ONE), 0.0);
    }
}
