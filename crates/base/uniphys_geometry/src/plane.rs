use glam::{DMat3, DVec3};

use crate::mass::outer;
use crate::{GeometryError, GeometryResult, SplitMix64, symmetric_eigen};

/// A plane through `point` with unit `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// A point on the plane, metres.
    pub point: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

impl Plane {
    /// Signed distance of `p` from the plane, metres (positive on the normal's side).
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        (p - self.point).dot(self.normal)
    }
}

/// Least-squares plane: through the centroid, normal along the eigenvector of the smallest
/// eigenvalue of the points' covariance (largest component positive).
///
/// Errors: fewer than 3 points, or points that are (nearly) collinear, are
/// [`GeometryError::NotEnoughInput`].
pub fn fit_plane(points: &[DVec3]) -> GeometryResult<Plane> {
    if points.len() < 3 {
        return Err(GeometryError::NotEnoughInput(format!(
            "a plane fit needs 3 points, got {}",
            points.len()
        )));
    }
    let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
    let covariance = points
        .iter()
        .fold(DMat3::ZERO, |acc, &p| acc + outer(p - centroid));
    let (values, vectors) = symmetric_eigen(covariance);
    // Collinear (or coincident) points: the middle eigenvalue vanishes next to the largest.
    if values.y.is_nan() || values.y <= 1e-12 * values.z {
        return Err(GeometryError::NotEnoughInput(
            "the points are collinear, so they do not define a plane".to_owned(),
        ));
    }
    Ok(Plane {
        point: centroid,
        normal: vectors.col(0),
    })
}

/// Robust plane fit: `iterations` random three-point hypotheses, the one with the most points
/// within `inlier_distance_m` wins (the earliest on ties), and the plane is refitted by least
/// squares on its inliers. Returns the refitted plane and the sorted indices of the points
/// within `inlier_distance_m` of it. Deterministic for a given `seed`. Collinear samples are
/// skipped; if every sample is (or with zero iterations), all points are the inliers.
///
/// Errors: as [`fit_plane`]; a negative or non-finite distance is an invalid parameter.
pub fn fit_plane_ransac(
    points: &[DVec3],
    inlier_distance_m: f64,
    iterations: usize,
    seed: u64,
) -> GeometryResult<(Plane, Vec<usize>)> {
    if !(inlier_distance_m.is_finite() && inlier_distance_m >= 0.0) {
        return Err(GeometryError::InvalidParameter(format!(
            "inlier distance must be finite and non-negative, got {inlier_distance_m}"
        )));
    }
    let n = points.len();
    if n < 3 {
        return fit_plane(points).map(|p| (p, Vec::new()));
    }
    let inliers_of = |plane: &Plane| -> Vec<usize> {
        (0..n)
            .filter(|&i| plane.distance(points[i]).abs() <= inlier_distance_m)
            .collect()
    };
    let mut rng = SplitMix64::new(seed);
    let mut best: Option<(usize, Plane)> = None;
    for _ in 0..iterations {
        let [a, b, c] = distinct_triple(&mut rng, n).map(|i| points[i]);
        let (u, v) = (b - a, c - a);
        let normal = u.cross(v);
        if normal.length() <= 1e-12 * u.length() * v.length() {
            continue;
        }
        let plane = Plane {
            point: a,
            normal: normal.normalize(),
        };
        let count = (0..n)
            .filter(|&i| plane.distance(points[i]).abs() <= inlier_distance_m)
            .count();
        if best.is_none_or(|(most, _)| count > most) {
            best = Some((count, plane));
        }
    }
    let support = match best {
        Some((_, plane)) => inliers_of(&plane),
        None => (0..n).collect(),
    };
    let support_points: Vec<DVec3> = support.iter().map(|&i| points[i]).collect();
    let plane = fit_plane(&support_points)?;
    Ok((plane, inliers_of(&plane)))
}

/// Three distinct indices below `n` (n >= 3), uniformly.
fn distinct_triple(rng: &mut SplitMix64, n: usize) -> [usize; 3] {
    let i = rng.below(n);
    let mut j = rng.below(n - 1);
    if j >= i {
        j += 1;
    }
    let (lo, hi) = (i.min(j), i.max(j));
    let mut k = rng.below(n - 2);
    if k >= lo {
        k += 1;
    }
    if k >= hi {
        k += 1;
    }
    [i, j, k]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points near the plane z = 0.5 x + 1 (normal (-0.5, 0, 1) / |.|) with +-0.01 noise.
    fn noisy_plane(count: usize, seed: u64) -> Vec<DVec3> {
        let mut rng = SplitMix64::new(seed);
        (0..count)
            .map(|_| {
                let (x, y) = (rng.next_f64() * 4.0 - 2.0, rng.next_f64() * 4.0 - 2.0);
                let noise = (rng.next_f64() - 0.5) * 0.02;
                DVec3::new(x, y, 0.5 * x + 1.0 + noise)
            })
            .collect()
    }

    fn true_normal() -> DVec3 {
        DVec3::new(-0.5, 0.0, 1.0).normalize()
    }

    #[test]
    fn least_squares_recovers_the_normal_of_noisy_points() {
        let plane = fit_plane(&noisy_plane(500, 1)).unwrap();
        assert!(plane.normal.dot(true_normal()) > 0.9999, "{}", plane.normal);
        assert!((plane.normal.length() - 1.0).abs() < 1e-12);
        // The centroid lies on the plane: z = 0.5 x + 1 within the noise.
        assert!((plane.point.z - 0.5 * plane.point.x - 1.0).abs() < 0.01);
    }

    #[test]
    fn exact_points_give_the_exact_plane_and_distance() {
        let pts = [
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(1.0, 0.0, 2.0),
            DVec3::new(0.0, 1.0, 2.0),
        ];
        let plane = fit_plane(&pts).unwrap();
        assert!((plane.normal - DVec3::Z).length() < 1e-12);
        assert!((plane.distance(DVec3::new(5.0, 5.0, 3.5)) - 1.5).abs() < 1e-12);
    }

    #[test]
    fn too_few_or_collinear_points_are_rejected() {
        assert!(matches!(
            fit_plane(&[DVec3::ZERO, DVec3::X]),
            Err(GeometryError::NotEnoughInput(_))
        ));
        let line: Vec<DVec3> = (0..5).map(|i| DVec3::X * f64::from(i)).collect();
        assert!(matches!(
            fit_plane(&line),
            Err(GeometryError::NotEnoughInput(_))
        ));
        assert!(matches!(
            fit_plane_ransac(&line[..2], 0.1, 10, 0),
            Err(GeometryError::NotEnoughInput(_))
        ));
    }

    #[test]
    fn ransac_ignores_thirty_percent_outliers() {
        let mut points = noisy_plane(700, 2);
        let mut rng = SplitMix64::new(3);
        for _ in 0..300 {
            points.push(DVec3::new(
                rng.next_f64() * 4.0 - 2.0,
                rng.next_f64() * 4.0 - 2.0,
                rng.next_f64() * 10.0 - 5.0,
            ));
        }
        let (plane, inliers) = fit_plane_ransac(&points, 0.02, 200, 7).unwrap();
        assert!(plane.normal.dot(true_normal()) > 0.9999, "{}", plane.normal);
        // All 700 plane points are inliers; the outliers mostly are not (a 0.04 m slab of a
        // 10 m range catches about 0.4 % of them).
        assert!((0..700).all(|i| inliers.binary_search(&i).is_ok()));
        assert!(inliers.len() < 720, "{}", inliers.len());
        assert!(inliers.windows(2).all(|w| w[0] < w[1]));
        // Least squares on everything is pulled off by the outliers.
        assert!(fit_plane(&points).unwrap().normal.dot(true_normal()) < 0.9999);
        assert_eq!(
            (plane, inliers),
            fit_plane_ransac(&points, 0.02, 200, 7).unwrap()
        );
    }

    #[test]
    fn distinct_triple_never_repeats_an_index() {
        let mut rng = SplitMix64::new(0);
        for _ in 0..1000 {
            let [i, j, k] = distinct_triple(&mut rng, 3);
            assert!(i != j && j != k && i != k && i < 3 && j < 3 && k < 3);
        }
    }
}
