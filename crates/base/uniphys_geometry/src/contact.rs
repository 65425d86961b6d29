use glam::DVec3;

use crate::kdtree::KdTree;
use crate::{GeometryError, GeometryResult, TriMesh, sample_points};

/// Parameters of [`contact_region`]. Distances are fractions of the object's diagonal, so the
/// result does not depend on the object's scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// Surface samples added to each mesh's vertices.
    pub samples_per_mesh: usize,
    /// First threshold, as a fraction of the object diagonal.
    pub start_fraction: f64,
    /// Threshold increment per step, as a fraction of the object diagonal.
    pub step_fraction: f64,
    /// Points needed to stop growing the threshold.
    pub min_points: usize,
    /// Most threshold increments before giving up.
    pub max_steps: usize,
    /// Seed of the surface samples.
    pub seed: u64,
}

impl Default for ContactParams {
    /// 1000 samples per mesh, thresholds starting at and growing by 0.5 % of the diagonal,
    /// at least 7 points, at most 1000 steps, seed 0.
    fn default() -> Self {
        Self {
            samples_per_mesh: 1000,
            start_fraction: 0.005,
            step_fraction: 0.005,
            min_points: 7,
            max_steps: 1000,
            seed: 0,
        }
    }
}

/// Where a part touches another: points of the other part near the part.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactRegion {
    /// Points of `other` (vertices first, then samples) closer than the threshold to a point of
    /// `part`.
    pub points: Vec<DVec3>,
    /// The final threshold, metres.
    pub threshold_m: f64,
    /// Threshold increments taken (0 if the first threshold sufficed; `max_steps` if the
    /// search gave up).
    pub steps: usize,
}

/// The contact region between a moving `part` and an `other` part.
///
/// Both meshes become point sets: all their vertices plus `samples_per_mesh` deterministic
/// surface samples. The region is the set of `other` points whose nearest `part` point is closer
/// than a threshold; the threshold starts at `start_fraction * object_diagonal_m` and grows by
/// `step_fraction * object_diagonal_m` until the region has at least `min_points` points, or
/// `max_steps` increments were made (then the region is whatever lies within that threshold).
/// Nearest distances come from a kd-tree over the `part` points.
///
/// Errors: a non-positive or non-finite diagonal or fraction is an invalid parameter; a mesh
/// with no vertices is [`GeometryError::NotEnoughInput`].
pub fn contact_region(
    part: &TriMesh,
    other: &TriMesh,
    object_diagonal_m: f64,
    params: &ContactParams,
) -> GeometryResult<ContactRegion> {
    let non_negative = |x: f64| x.is_finite() && x >= 0.0;
    let positive = |x: f64| x.is_finite() && x > 0.0;
    let valid = positive(object_diagonal_m)
        && non_negative(params.start_fraction)
        && positive(params.step_fraction);
    if !valid {
        return Err(GeometryError::InvalidParameter(format!(
            "contact region needs a positive diagonal and step and a non-negative start, got \
             diagonal {object_diagonal_m} m, start {}, step {}",
            params.start_fraction, params.step_fraction
        )));
    }
    let part_points = point_set(part, params.samples_per_mesh, params.seed);
    let other_points = point_set(other, params.samples_per_mesh, params.seed.wrapping_add(1));
    if part_points.is_empty() || other_points.is_empty() {
        return Err(GeometryError::NotEnoughInput(
            "contact region needs vertices on both meshes".to_owned(),
        ));
    }
    let tree = KdTree::new(part_points);
    let distances: Vec<f64> = other_points
        .iter()
        .map(|&q| tree.nearest_distance(q))
        .collect();
    // The region reaches `min_points` once the threshold exceeds the min_points-th smallest
    // distance.
    let needed = match params.min_points.checked_sub(1) {
        None => Some(f64::NEG_INFINITY),
        Some(k) if k < distances.len() => {
            let mut sorted = distances.clone();
            sorted.sort_by(f64::total_cmp);
            Some(sorted[k])
        }
        Some(_) => None,
    };
    let threshold_at =
        |s: usize| (params.start_fraction + s as f64 * params.step_fraction) * object_diagonal_m;
    let mut steps = 0;
    while steps < params.max_steps && needed.is_none_or(|d| d >= threshold_at(steps)) {
        steps += 1;
    }
    let threshold_m = threshold_at(steps);
    let points = other_points
        .iter()
        .zip(&distances)
        .filter(|&(_, &d)| d < threshold_m)
        .map(|(&p, _)| p)
        .collect();
    Ok(ContactRegion {
        points,
        threshold_m,
        steps,
    })
}

/// Approximate minimum distance between two meshes, metres: the smallest distance between
/// their point sets (all vertices plus 1000 surface samples each, seed 0 for `a` and 1 for `b`).
/// It is never below the true surface distance and exceeds it by at most about the sample
/// spacing; meshes that share a vertex position give 0. Infinite if either mesh has no
/// vertices. For many pairs of the same meshes, [`DistanceProbe`] builds each mesh's points once.
#[must_use]
pub fn min_distance_m(a: &TriMesh, b: &TriMesh) -> f64 {
    DistanceProbe::new(a).min_distance_m(&DistanceProbe::new(b))
}

/// One mesh prepared for [`min_distance_m`] against many others: its point set with seed 0 in
/// a kd-tree (the mesh as `a`) and with seed 1 as query points (the mesh as `b`).
pub struct DistanceProbe {
    tree: KdTree,
    queries: Vec<DVec3>,
}

impl DistanceProbe {
    /// Samples `mesh` as [`min_distance_m`] does.
    #[must_use]
    pub fn new(mesh: &TriMesh) -> Self {
        let samples = ContactParams::default().samples_per_mesh;
        Self {
            tree: KdTree::new(point_set(mesh, samples, 0)),
            queries: point_set(mesh, samples, 1),
        }
    }

    /// [`min_distance_m`] of this mesh (as `a`) and `other` (as `b`). Exact over the point sets;
    /// each query only looks closer than the best distance so far, so points of `other` far
    /// from this mesh cost a box test.
    #[must_use]
    pub fn min_distance_m(&self, other: &Self) -> f64 {
        if self.tree.is_empty() {
            return f64::INFINITY;
        }
        other.queries.iter().fold(f64::INFINITY, |best, &q| {
            self.tree.nearest_distance_within(q, best).unwrap_or(best)
        })
    }
}

/// All vertices of `mesh`, then `samples` surface samples.
fn point_set(mesh: &TriMesh, samples: usize, seed: u64) -> Vec<DVec3> {
    let mut points = mesh.positions.clone();
    points.extend(sample_points(mesh, samples, seed));
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_shapes::unit_box;

    fn slab(z0: f64, z1: f64) -> TriMesh {
        unit_box(DVec3::new(0.0, 0.0, z0), DVec3::new(1.0, 1.0, z1))
    }

    #[test]
    fn the_probe_finds_the_least_distance_of_every_pair_of_points() {
        let (a, b) = (
            slab(0.0, 1.0),
            unit_box(DVec3::new(1.3, 0.2, 1.6), DVec3::new(2.0, 0.9, 2.5)),
        );
        let (a_points, b_points) = (point_set(&a, 1000, 0), point_set(&b, 1000, 1));
        let brute = a_points
            .iter()
            .flat_map(|p| b_points.iter().map(move |q| p.distance(*q)))
            .fold(f64::INFINITY, f64::min);
        assert_eq!(min_distance_m(&a, &b), brute);
        assert_eq!(
            DistanceProbe::new(&a).min_distance_m(&DistanceProbe::new(&b)),
            brute
        );
    }

    #[test]
    fn stacked_boxes_touch_on_the_shared_face() {
        let (part, other) = (slab(1.0, 2.0), slab(0.0, 1.0));
        let diagonal = 6f64.sqrt();
        let params = ContactParams::default();
        let region = contact_region(&part, &other, diagonal, &params).unwrap();
        assert!(region.points.len() >= 7);
        let expected = (0.005 + region.steps as f64 * 0.005) * diagonal;
        assert!((region.threshold_m - expected).abs() < 1e-15);
        // Every region point is within the threshold of the part (z >= 1), and on the other
        // box (z <= 1): so within the threshold below the interface.
        for p in &region.points {
            assert!(p.z <= 1.0 && p.z > 1.0 - region.threshold_m, "{p}");
        }
        // The four top corners of the lower box coincide with part vertices.
        let corners = region.points.iter().filter(|p| p.z == 1.0).count();
        assert!(corners >= 4);
        assert_eq!(
            region,
            contact_region(&part, &other, diagonal, &params).unwrap()
        );
    }

    #[test]
    fn a_gap_makes_the_threshold_grow_past_it() {
        let gap = 0.05;
        let diagonal = 6f64.sqrt();
        let params = ContactParams::default();
        let touching = contact_region(&slab(1.0, 2.0), &slab(0.0, 1.0), diagonal, &params).unwrap();
        let apart = contact_region(
            &slab(1.0 + gap, 2.0 + gap),
            &slab(0.0, 1.0),
            diagonal,
            &params,
        )
        .unwrap();
        // Start threshold 0.0122 m < gap: at least (0.05 / 0.0122) - 1 = 3.1 -> 4 steps.
        assert!(apart.steps >= 4, "{}", apart.steps);
        assert!(apart.threshold_m > gap && apart.threshold_m > touching.threshold_m);
        assert!(apart.points.len() >= 7);
        for p in &apart.points {
            assert!(p.z <= 1.0 && p.z > 1.0 + gap - apart.threshold_m, "{p}");
        }
    }

    #[test]
    fn search_gives_up_after_max_steps() {
        let params = ContactParams {
            min_points: 1_000_000,
            max_steps: 3,
            ..ContactParams::default()
        };
        let region = contact_region(&slab(1.0, 2.0), &slab(0.0, 1.0), 2.0, &params).unwrap();
        assert_eq!(region.steps, 3);
        // (0.005 + 3 * 0.005) * 2 m.
        assert!((region.threshold_m - 0.04).abs() < 1e-15);
        assert!(region.points.iter().all(|p| p.z > 0.96));
    }

    #[test]
    fn bad_diagonal_or_empty_mesh_is_an_error() {
        let params = ContactParams::default();
        let b = slab(0.0, 1.0);
        assert!(matches!(
            contact_region(&b, &b, 0.0, &params),
            Err(GeometryError::InvalidParameter(_))
        ));
        assert!(matches!(
            contact_region(&b, &TriMesh::default(), 1.0, &params),
            Err(GeometryError::NotEnoughInput(_))
        ));
    }

    #[test]
    fn min_distance_sees_the_gap_between_aligned_boxes() {
        // The corners sit straight above each other: exactly the gap.
        let d = min_distance_m(&slab(1.05, 2.0), &slab(0.0, 1.0));
        assert!((d - 0.05).abs() < 1e-12, "{d}");
        assert_eq!(min_distance_m(&slab(1.0, 2.0), &slab(0.0, 1.0)), 0.0);
        assert_eq!(
            min_distance_m(&TriMesh::default(), &slab(0.0, 1.0)),
            f64::INFINITY
        );
    }
}
