//! Point sets for the crate's unit tests.

use uniphys_geometry::DVec3;

/// Points filling the box `[lo, hi]` on a grid of `n + 1` points a side (a flat box is a
/// patch, a thin one a panel).
pub(crate) fn box_grid(lo: DVec3, hi: DVec3, n: u32) -> Vec<DVec3> {
    let mut out = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            for k in 0..=n {
                let t = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) / f64::from(n);
                out.push(lo + (hi - lo) * t);
            }
        }
    }
    out
}
