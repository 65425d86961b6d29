//! Convex outlines of points in a plane (Andrew's monotone chain) and the area a polygon
//! encloses.

/// The convex outline of points in a plane, counter-clockwise, without repeated points. Fewer
/// than three distinct points come back as they are (sorted).
#[must_use]
pub fn convex_outline(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * sorted.len());
    for pass in [false, true] {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass {
            Box::new(sorted.iter().rev())
        } else {
            Box::new(sorted.iter())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        // The last point of each chain starts the other.
        hull.pop();
    }
    hull
}

/// The area enclosed by a closed polygon (the shoelace formula; positive counter-clockwise).
#[must_use]
pub fn outline_area(outline: &[[f64; 2]]) -> f64 {
    let n = outline.len();
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (outline[i], outline[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
}

/// Twice the signed area of the triangle `o`, `a`, `b`: positive when it turns left.
fn turn(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outline_of_a_square_with_inner_points_is_its_four_corners() {
        let mut points = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        points.extend([[0.5, 0.5], [0.2, 0.7], [0.5, 0.0]]);
        let hull = convex_outline(&points);
        assert_eq!(hull.len(), 4, "{hull:?}");
        for corner in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]] {
            assert!(hull.contains(&corner), "{corner:?} missing from {hull:?}");
        }
    }

    #[test]
    fn a_square_outline_encloses_its_area_and_a_segment_none() {
        let square = convex_outline(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0], [1.0, 0.5]]);
        assert!((outline_area(&square) - 2.0).abs() < 1e-12);
        assert!(outline_area(&convex_outline(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])).abs() < 1e-12);
    }
}
