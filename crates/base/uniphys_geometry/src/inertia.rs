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
