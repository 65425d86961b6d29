use glam::DMat3;

use crate::symmetric_eigen;

/// Relative tolerance of the symmetry and triangle-inequality checks.
const RELATIVE_TOLERANCE: f64 = 1e-9;

/// Whether an inertia tensor can belong to a real rigid body: finite, symmetric, positive
/// definite, and its principal moments satisfy the triangle inequality `A + B >= C` (all
/// checks with a relative tolerance of 1e-9 of the trace, so a flat plate with `A + B = C`
/// passes).
#[must_use]
pub fn inertia_is_physical(i: &DMat3) -> bool {
    let cols = [i.x_axis, i.y_axis, i.z_axis];
    if !cols.iter().all(|c| c.is_finite()) {
        return false;
    }
    let trace = i.x_axis.x + i.y_axis.y + i.z_axis.z;
    if trace <= 0.0 {
        return false;
    }
    let tol = RELATIVE_TOLERANCE * trace;
    let symmetric = (0..3).all(|r| (0..3).all(|c| (cols[c][r] - cols[r][c]).abs() <= tol));
    if !symmetric {
        return false;
    }
    let (moments, _) = symmetric_eigen(*i);
    moments.x > 0.0 && moments.x + moments.y >= moments.z - tol
}

/// Relative margin by which [`with_triangle_margin`] keeps `A + B` above `C`.
pub const TRIANGLE_MARGIN: f64 = 1e-6;

/// The tensor with `delta` added to each principal moment (its axes unchanged), the least
/// `delta >= 0` that makes `A + B >= C` hold by [`TRIANGLE_MARGIN`] of the trace. A flat plate
/// or a thin rod sits exactly on the bound, and a simulator that diagonalises the tensor again
/// after it was written to ten digits (MuJoCo) may find it just below and refuse the model.
#[must_use]
pub fn with_triangle_margin(i: DMat3) -> DMat3 {
    let (moments, _) = symmetric_eigen(i);
    let trace = moments.x + moments.y + moments.z;
    let mut sorted = moments.to_array();
    sorted.sort_by(f64::total_cmp);
    let slack = sorted[0] + sorted[1] - sorted[2];
    let delta = (TRIANGLE_MARGIN * trace - slack).max(0.0);
    i + DMat3::from_diagonal(glam::DVec3::splat(delta))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    #[test]
    fn box_and_thin_plate_tensors_are_physical() {
        // 1 x 2 x 3 box of density 1.
        assert!(inertia_is_physical(&DMat3::from_diagonal(DVec3::new(
            6.5, 5.0, 2.5
        ))));
        // Thin square plate: A = B = m a^2 / 12, C = A + B exactly.
        assert!(inertia_is_physical(&DMat3::from_diagonal(DVec3::new(
            1.0, 1.0, 2.0
        ))));
    }

    #[test]
    fn a_flat_plate_gets_a_margin_and_a_box_is_unchanged() {
        let r = DMat3::from_rotation_z(0.4);
        let plate = r * DMat3::from_diagonal(DVec3::new(1.0, 1.0, 2.0)) * r.transpose();
        let (moments, _) = symmetric_eigen(with_triangle_margin(plate));
        let mut m = moments.to_array();
        m.sort_by(f64::total_cmp);
        assert!(m[0] + m[1] - m[2] >= 0.99 * TRIANGLE_MARGIN * 4.0, "{m:?}");
        assert!((m[2] - 2.0).abs() < 1e-5);
        let cuboid = DMat3::from_diagonal(DVec3::new(6.5, 5.0, 2.5));
        assert_eq!(with_triangle_margin(cuboid), cuboid);
    }

    #[test]
    fn triangle_inequality_violation_is_rejected() {
        // 1 + 1 < 3: no mass distribution has these principal moments.
        assert!(!inertia_is_physical(&DMat3::from_diagonal(DVec3::new(
            1.0, 1.0, 3.0
        ))));
    }

    #[test]
    fn non_positive_asymmetric_or_nan_tensors_are_rejected() {
        assert!(!inertia_is_physical(&DMat3::from_diagonal(DVec3::new(
            0.0, 1.0, 1.0
        ))));
        assert!(!inertia_is_physical(&DMat3::from_diagonal(DVec3::new(
            -1.0, 2.0, 2.0
        ))));
        let mut asymmetric = DMat3::from_diagonal(DVec3::splat(2.0));
        asymmetric.x_axis.y = 0.5;
        assert!(!inertia_is_physical(&asymmetric));
        assert!(!inertia_is_physical(&DMat3::from_diagonal(DVec3::new(
            f64::NAN,
            1.0,
            1.0
        ))));
        assert!(!inertia_is_physical(&DMat3::ZERO));
    }

    #[test]
    fn rotated_physical_tensor_stays_physical() {
        let r = DMat3::from_rotation_y(0.7) * DMat3::from_rotation_x(0.3);
        let i = r * DMat3::from_diagonal(DVec3::new(6.5, 5.0, 2.5)) * r.transpose();
        assert!(inertia_is_physical(&i));
        let bad = r * DMat3::from_diagonal(DVec3::new(1.0, 1.0, 3.0)) * r.transpose();
        assert!(!inertia_is_physical(&bad));
    }
}
