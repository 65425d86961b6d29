//! Per-pair kinematic measures: sign-invariant axis angle, point-to-line distance and the 1-D IoU
//! of canonicalised ranges.

/// Tolerance for degenerate vectors and intervals.
const TINY: f64 = 1e-12;

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(v);
    (n.is_finite() && n > TINY).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// Sign-invariant angle in degrees between two axes: `acos(clamp(|a·g|, 0, 1))` after
/// normalising both. `None` for zero or non-finite vectors.
#[must_use]
pub fn axis_angular_error_degrees(pred: [f64; 3], gt: [f64; 3]) -> Option<f64> {
    let a = unit(pred)?;
    let g = unit(gt)?;
    let dot = (a[0] * g[0] + a[1] * g[1] + a[2] * g[2])
        .abs()
        .clamp(0.0, 1.0);
    Some(dot.acos().to_degrees())
}

/// Distance from `point` to the line through `line_point` along `line_dir`:
/// `|(p - p_gt) x ĝ|`. `None` for a zero or non-finite direction or non-finite points.
#[must_use]
pub fn point_to_line_distance(
    point: [f64; 3],
    line_point: [f64; 3],
    line_dir: [f64; 3],
) -> Option<f64> {
    let g = unit(line_dir)?;
    let d = [
        point[0] - line_point[0],
        point[1] - line_point[1],
        point[2] - line_point[2],
    ];
    let c = [
        d[1] * g[2] - d[2] * g[1],
        d[2] * g[0] - d[0] * g[2],
        d[0] * g[1] - d[1] * g[0],
    ];
    let dist = norm(c);
    dist.is_finite().then_some(dist)
}

/// Canonical interval `[min(|a|, |b|), max(|a|, |b|)]` (the sign of a range is ignored).
#[must_use]
pub fn canonical_interval(range: [f64; 2]) -> [f64; 2] {
    let (a, b) = (range[0].abs(), range[1].abs());
    [a.min(b), a.max(b)]
}

/// 1-D IoU of two ranges after [`canonical_interval`]:
/// `max(0, min(hi) - max(lo)) / (max(hi) - min(lo))`; when the union is `<= 1e-12`, 1.0 if the
/// lower bounds are equal within 1e-12, else 0.0. `None` for non-finite bounds.
#[must_use]
pub fn interval_iou(pred: [f64; 2], gt: [f64; 2]) -> Option<f64> {
    if !pred.iter().chain(gt.iter()).all(|v| v.is_finite()) {
        return None;
    }
    let p = canonical_interval(pred);
    let g = canonical_interval(gt);
    let union = p[1].max(g[1]) - p[0].min(g[0]);
    if union <= TINY {
        return Some(if (p[0] - g[0]).abs() <= TINY {
            1.0
        } else {
            0.0
        });
    }
    let inter = (p[1].min(g[1]) - p[0].max(g[0])).max(0.0);
    Some(inter / union)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = 1e-9;

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < EPS)
    }

    #[test]
    fn opposite_axes_have_zero_error() {
        assert!(close(
            axis_angular_error_degrees([0.0, 0.0, 1.0], [0.0, 0.0, -1.0]),
            0.0
        ));
    }

    #[test]
    fn perpendicular_axes_have_ninety_degrees() {
        assert!(close(
            axis_angular_error_degrees([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            90.0
        ));
    }

    #[test]
    fn axes_are_normalised_before_the_angle() {
        // [1,1,0] vs [0,3,0]: 45 degrees regardless of length.
        assert!(close(
            axis_angular_error_degrees([1.0, 1.0, 0.0], [0.0, 3.0, 0.0]),
            45.0
        ));
    }

    #[test]
    fn zero_axis_is_skipped() {
        assert_eq!(
            axis_angular_error_degrees([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            None
        );
        assert_eq!(
            axis_angular_error_degrees([0.0, 0.0, 1.0], [0.0, 0.0, 0.0]),
            None
        );
    }

    #[test]
    fn pivot_distance_is_to_the_gt_axis_line_not_the_gt_point() {
        let d = point_to_line_distance([1.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        assert!(close(d, 2f64.sqrt()));
        // Moving along the line does not change the distance.
        let d = point_to_line_distance([1.0, 1.0, 7.0], [0.0, 0.0, 0.0], [0.0, 0.0, -4.0]);
        assert!(close(d, 2f64.sqrt()));
    }

    #[test]
    fn overlapping_intervals_have_quarter_iou() {
        assert!(close(interval_iou([0.0, 1.0], [0.5, 2.0]), 0.25));
    }

    #[test]
    fn interval_sign_is_ignored_by_canonicalisation() {
        assert_eq!(canonical_interval([-1.0, 0.0]), [0.0, 1.0]);
        assert!(close(interval_iou([-1.0, 0.0], [0.0, 1.0]), 1.0));
    }

    #[test]
    fn disjoint_intervals_have_zero_iou() {
        assert!(close(interval_iou([0.0, 1.0], [2.0, 3.0]), 0.0));
    }

    #[test]
    fn degenerate_intervals_at_same_lower_bound_have_iou_one() {
        assert!(close(interval_iou([0.3, 0.3], [-0.3, 0.3]), 1.0));
    }

    #[test]
    fn tiny_union_counts_lower_bounds_within_tolerance_as_equal() {
        // Union 2e-13 <= 1e-12 and the lower bounds 0 and 2e-13 are within 1e-12 -> 1.0.
        assert!(close(interval_iou([0.0, 0.0], [2e-13, 2e-13]), 1.0));
        // A point and a different point: union 1.0 > 1e-12, intersection 0 -> 0.0.
        assert!(close(interval_iou([0.0, 0.0], [1.0, 1.0]), 0.0));
    }

    #[test]
    fn a_point_inside_an_interval_has_zero_iou() {
        assert!(close(interval_iou([0.5, 0.5], [0.0, 1.0]), 0.0));
    }

    #[test]
    fn non_finite_interval_is_skipped() {
        assert_eq!(interval_iou([0.0, f64::NAN], [0.0, 1.0]), None);
    }
}
