use glam::DVec3;

use crate::{GeometryError, GeometryResult, SplitMix64};

/// The result of [`kmeans`].
#[derive(Debug, Clone, PartialEq)]
pub struct KMeans {
    /// Cluster centres (means of their points).
    pub centres: Vec<DVec3>,
    /// Index into `centres` of each input point's cluster.
    pub labels: Vec<usize>,
}

/// K-means clustering: k-means++ seeding, then Lloyd iterations until the labels stop changing
/// or `max_iterations` updates were made. `k` is clipped to the number of distinct points, so
/// no cluster starts empty; a cluster that empties later keeps its centre. Ties go to the
/// lowest centre index. Deterministic for a given `seed`.
///
/// Errors: no points, or `k == 0`, is [`GeometryError::NotEnoughInput`].
pub fn kmeans(
    points: &[DVec3],
    k: usize,
    seed: u64,
    max_iterations: usize,
) -> GeometryResult<KMeans> {
    if points.is_empty() || k == 0 {
        return Err(GeometryError::NotEnoughInput(format!(
            "k-means needs points and k > 0, got {} points and k = {k}",
            points.len()
        )));
    }
    let k = k.min(distinct_count(points));
    let mut centres = seed_centres(points, k, &mut SplitMix64::new(seed));
    let mut labels = assign(points, &centres);
    for _ in 0..max_iterations {
        let mut sums = vec![DVec3::ZERO; centres.len()];
        let mut counts = vec![0usize; centres.len()];
        for (p, &label) in points.iter().zip(&labels) {
            sums[label] += *p;
            counts[label] += 1;
        }
        for ((centre, sum), &count) in centres.iter_mut().zip(&sums).zip(&counts) {
            if count > 0 {
                *centre = *sum / count as f64;
            }
        }
        let next = assign(points, &centres);
        if next == labels {
            break;
        }
        labels = next;
    }
    Ok(KMeans { centres, labels })
}

fn distinct_count(points: &[DVec3]) -> usize {
    let mut keys: Vec<[u64; 3]> = points
        .iter()
        .map(|p| p.to_array().map(|c| (c + 0.0).to_bits()))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.len()
}

/// k-means++: the first centre uniformly, each further one with probability proportional to
/// the squared distance to the nearest chosen centre. `k` must not exceed the distinct points.
fn seed_centres(points: &[DVec3], k: usize, rng: &mut SplitMix64) -> Vec<DVec3> {
    let mut centres = vec![points[rng.below(points.len())]];
    let mut nearest: Vec<f64> = points
        .iter()
        .map(|p| p.distance_squared(centres[0]))
        .collect();
    while centres.len() < k {
        let total: f64 = nearest.iter().sum();
        if total <= 0.0 {
            break;
        }
        let target = rng.next_f64() * total;
        let mut running = 0.0;
        let mut chosen = None;
        for (i, &d) in nearest.iter().enumerate() {
            running += d;
            if d > 0.0 {
                chosen = Some(i);
                if running > target {
                    break;
                }
            }
        }
        let Some(chosen) = chosen else { break };
        let centre = points[chosen];
        centres.push(centre);
        for (n, p) in nearest.iter_mut().zip(points) {
            *n = n.min(p.distance_squared(centre));
        }
    }
    centres
}

fn assign(points: &[DVec3], centres: &[DVec3]) -> Vec<usize> {
    points
        .iter()
        .map(|p| {
            let mut best = (f64::INFINITY, 0);
            for (i, c) in centres.iter().enumerate() {
                let d = p.distance_squared(*c);
                if d < best.0 {
                    best = (d, i);
                }
            }
            best.1
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 50 points within +-0.1 of each of (0,0,0), (10,0,0), (0,10,0), interleaved.
    fn three_clusters() -> Vec<DVec3> {
        let mut rng = SplitMix64::new(5);
        let centres = [
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(0.0, 10.0, 0.0),
        ];
        (0..150)
            .map(|i| {
                let jitter = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5;
                centres[i % 3] + jitter * 0.2
            })
            .collect()
    }

    #[test]
    fn three_separated_clusters_are_recovered() {
        let points = three_clusters();
        let result = kmeans(&points, 3, 1, 100).unwrap();
        assert_eq!(result.centres.len(), 3);
        // Points of one true cluster share a label, and the three labels differ.
        let label_of = |c: usize| result.labels[c];
        for (i, &label) in result.labels.iter().enumerate() {
            assert_eq!(label, label_of(i % 3), "point {i}");
        }
        assert!(
            label_of(0) != label_of(1) && label_of(1) != label_of(2) && label_of(0) != label_of(2)
        );
        // Each centre is the mean of its cluster: within the jitter of the true centre.
        let truth = [
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(0.0, 10.0, 0.0),
        ];
        for (c, t) in truth.iter().enumerate() {
            assert!(result.centres[label_of(c)].distance(*t) < 0.1);
        }
    }

    #[test]
    fn same_seed_gives_the_same_clustering() {
        let points = three_clusters();
        assert_eq!(
            kmeans(&points, 4, 9, 50).unwrap(),
            kmeans(&points, 4, 9, 50).unwrap()
        );
    }

    #[test]
    fn k_is_clipped_to_the_distinct_points() {
        let points = [DVec3::ZERO, DVec3::ZERO, DVec3::X, DVec3::X, DVec3::ZERO];
        let result = kmeans(&points, 4, 0, 10).unwrap();
        assert_eq!(result.centres.len(), 2);
        assert_eq!(result.labels[0], result.labels[1]);
        assert_ne!(result.labels[0], result.labels[2]);
        assert_eq!(result.centres[result.labels[2]], DVec3::X);
    }

    #[test]
    fn empty_input_or_zero_k_is_an_error() {
        assert!(matches!(
            kmeans(&[], 3, 0, 10),
            Err(GeometryError::NotEnoughInput(_))
        ));
        assert!(matches!(
            kmeans(&[DVec3::ZERO], 0, 0, 10),
            Err(GeometryError::NotEnoughInput(_))
        ));
    }
}
