//! Shared helpers: ALDE, MnRE, absolute error and a running mean that ignores invalid values.

/// Absolute log difference error `|ln p - ln g|`; `None` unless both are finite and > 0.
#[must_use]
pub fn alde(pred: f64, gt: f64) -> Option<f64> {
    (pred.is_finite() && gt.is_finite() && pred > 0.0 && gt > 0.0)
        .then(|| (pred.ln() - gt.ln()).abs())
}

/// Min-ratio `min(p/g, g/p)` in `[0, 1]` (higher is better); `None` unless both are finite and > 0.
#[must_use]
pub fn mnre(pred: f64, gt: f64) -> Option<f64> {
    (pred.is_finite() && gt.is_finite() && pred > 0.0 && gt > 0.0)
        .then(|| (pred / gt).min(gt / pred))
}

/// Absolute error `|p - g|`; `None` unless both are finite.
#[must_use]
pub fn abs_error(pred: f64, gt: f64) -> Option<f64> {
    (pred.is_finite() && gt.is_finite()).then(|| (pred - gt).abs())
}

/// A running mean that ignores `None` and non-finite values.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RunningMean {
    sum: f64,
    count: u64,
}

impl RunningMean {
    /// Adds a value; `None` and non-finite values are ignored.
    pub fn push(&mut self, value: Option<f64>) {
        if let Some(v) = value.filter(|v| v.is_finite()) {
            self.sum += v;
            self.count += 1;
        }
    }

    /// Number of values accepted so far.
    #[must_use]
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The mean of the accepted values, `None` if there are none.
    #[must_use]
    pub fn mean(&self) -> Option<f64> {
        let n = self.count as f64;
        (self.count > 0).then(|| self.sum / n)
    }
}

/// Accuracy as a running mean of 1.0 (hit) / 0.0 (miss).
pub(crate) fn hit(value: bool) -> Option<f64> {
    Some(if value { 1.0 } else { 0.0 })
}

/// Whether a metric is present and equals `b` within 1e-12 (test helper).
#[cfg(test)]
pub(crate) fn close(a: Option<f64>, b: f64) -> bool {
    a.is_some_and(|a| (a - b).abs() < 1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = 1e-12;

    #[test]
    fn alde_of_two_and_one_is_ln_two() {
        let v = alde(2.0, 1.0).expect("both positive");
        assert!((v - 2f64.ln()).abs() < EPS);
        assert!((alde(1.0, 2.0).expect("both positive") - 2f64.ln()).abs() < EPS);
    }

    #[test]
    fn alde_and_mnre_reject_non_positive_or_non_finite() {
        assert_eq!(alde(0.0, 1.0), None);
        assert_eq!(alde(1.0, -1.0), None);
        assert_eq!(alde(f64::NAN, 1.0), None);
        assert_eq!(mnre(0.0, 1.0), None);
        assert_eq!(mnre(1.0, f64::INFINITY), None);
    }

    #[test]
    fn mnre_of_two_and_one_is_one_half_either_way() {
        assert!((mnre(2.0, 1.0).expect("positive") - 0.5).abs() < EPS);
        assert!((mnre(1.0, 2.0).expect("positive") - 0.5).abs() < EPS);
    }

    #[test]
    fn abs_error_is_absolute_difference() {
        assert!((abs_error(0.2, 0.5).expect("finite") - 0.3).abs() < EPS);
        assert_eq!(abs_error(f64::NAN, 0.5), None);
    }

    #[test]
    fn running_mean_ignores_none_and_non_finite() {
        let mut m = RunningMean::default();
        assert_eq!(m.mean(), None);
        m.push(Some(1.0));
        m.push(None);
        m.push(Some(f64::NAN));
        m.push(Some(f64::INFINITY));
        m.push(Some(3.0));
        assert_eq!(m.count(), 2);
        assert!((m.mean().expect("two values") - 2.0).abs() < EPS);
    }
}
