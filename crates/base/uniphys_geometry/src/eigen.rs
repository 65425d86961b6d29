use glam::{DMat3, DVec3};

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations.
///
/// Returns the eigenvalues in ascending order and the unit eigenvectors as the columns of the
/// matrix, in the same order. Only the symmetric part `(m + m^T) / 2` is used. Each eigenvector's
/// largest-magnitude component is made positive so the result is unique for distinct eigenvalues.
#[must_use]
pub fn symmetric_eigen(m: DMat3) -> (DVec3, DMat3) {
    let mut a = [[0.0f64; 3]; 3];
    for (r, row) in a.iter_mut().enumerate() {
        for (c, value) in row.iter_mut().enumerate() {
            *value = 0.5 * (m.col(c)[r] + m.col(r)[c]);
        }
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale: f64 = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _sweep in 0..64 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off.sqrt() <= f64::EPSILON * 1e-3 * scale || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            rotate(&mut a, &mut v, p, q);
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let values = DVec3::new(
        a[order[0]][order[0]],
        a[order[1]][order[1]],
        a[order[2]][order[2]],
    );
    let column = |k: usize| {
        let c = DVec3::new(v[0][k], v[1][k], v[2][k]);
        let largest = if c.x.abs() >= c.y.abs() && c.x.abs() >= c.z.abs() {
            c.x
        } else if c.y.abs() >= c.z.abs() {
            c.y
        } else {
            c.z
        };
        if largest < 0.0 { -c } else { c }
    };
    let vectors = DMat3::from_cols(column(order[0]), column(order[1]), column(order[2]));
    (values, vectors)
}

/// One Jacobi rotation zeroing `a[p][q]`; accumulates the rotation into the columns of `v`.
fn rotate(a: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize) {
    let apq = a[p][q];
    if apq == 0.0 {
        return;
    }
    let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
    let t = if theta.abs() > 1e150 {
        0.5 / theta
    } else {
        theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
    };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    a[p][p] -= t * apq;
    a[q][q] += t * apq;
    a[p][q] = 0.0;
    a[q][p] = 0.0;
    for r in 0..3 {
        if r != p && r != q {
            let (arp, arq) = (a[r][p], a[r][q]);
            a[r][p] = c * arp - s * arq;
            a[p][r] = a[r][p];
            a[r][q] = s * arp + c * arq;
            a[q][r] = a[r][q];
        }
        let (vrp, vrq) = (v[r][p], v[r][q]);
        v[r][p] = c * vrp - s * vrq;
        v[r][q] = s * vrp + c * vrq;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_mat_close(a: DMat3, b: DMat3, tol: f64) {
        for c in 0..3 {
            assert!(
                (a.col(c) - b.col(c)).length() < tol,
                "column {c}: {a:?} vs {b:?}"
            );
        }
    }

    #[test]
    fn diagonal_matrix_gives_sorted_values_and_axis_vectors() {
        let (values, vectors) = symmetric_eigen(DMat3::from_diagonal(DVec3::new(3.0, 1.0, 2.0)));
        assert_eq!(values, DVec3::new(1.0, 2.0, 3.0));
        assert_mat_close(
            vectors,
            DMat3::from_cols(DVec3::Y, DVec3::Z, DVec3::X),
            1e-15,
        );
    }

    #[test]
    fn two_by_two_block_has_hand_computed_eigenpairs() {
        // [[2,1,0],[1,2,0],[0,0,5]]: eigenvalues 1 (x-y)/sqrt2, 3 (x+y)/sqrt2, 5 z.
        let m = DMat3::from_cols(
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(0.0, 0.0, 5.0),
        );
        let (values, vectors) = symmetric_eigen(m);
        assert!(
            (values - DVec3::new(1.0, 3.0, 5.0)).length() < 1e-12,
            "{values}"
        );
        let h = std::f64::consts::FRAC_1_SQRT_2;
        // (h, -h) and (-h, h) tie under the sign rule, so compare up to sign.
        assert!((vectors.col(0).dot(DVec3::new(h, -h, 0.0)).abs() - 1.0).abs() < 1e-12);
        assert!((vectors.col(1) - DVec3::new(h, h, 0.0)).length() < 1e-12);
        assert!((vectors.col(2) - DVec3::Z).length() < 1e-12);
    }

    #[test]
    fn decomposition_reconstructs_a_general_symmetric_matrix() {
        let m = DMat3::from_cols(
            DVec3::new(4.0, -2.0, 0.5),
            DVec3::new(-2.0, 3.0, 1.5),
            DVec3::new(0.5, 1.5, -1.0),
        );
        let (values, vectors) = symmetric_eigen(m);
        assert!(values.x <= values.y && values.y <= values.z);
        let rebuilt = vectors * DMat3::from_diagonal(values) * vectors.transpose();
        assert_mat_close(rebuilt, m, 1e-12);
        assert_mat_close(vectors.transpose() * vectors, DMat3::IDENTITY, 1e-12);
        // Trace is preserved: 4 + 3 - 1 = 6.
        assert!((values.element_sum() - 6.0).abs() < 1e-12);
    }

    #[test]
    fn repeated_eigenvalues_still_give_an_orthonormal_basis() {
        let (values, vectors) = symmetric_eigen(DMat3::from_diagonal(DVec3::splat(2.0)));
        assert_eq!(values, DVec3::splat(2.0));
        assert_mat_close(vectors.transpose() * vectors, DMat3::IDENTITY, 1e-15);
    }

    proptest::proptest! {
        #[test]
        fn any_symmetric_matrix_is_reconstructed(
            d in proptest::array::uniform3(-10.0f64..10.0),
            o in proptest::array::uniform3(-10.0f64..10.0),
        ) {
            let m = DMat3::from_cols(
                DVec3::new(d[0], o[0], o[1]),
                DVec3::new(o[0], d[1], o[2]),
                DVec3::new(o[1], o[2], d[2]),
            );
            let (values, vectors) = symmetric_eigen(m);
            proptest::prop_assert!(values.x <= values.y && values.y <= values.z);
            assert_mat_close(vectors * DMat3::from_diagonal(values) * vectors.transpose(), m, 1e-9);
            assert_mat_close(vectors.transpose() * vectors, DMat3::IDENTITY, 1e-12);
        }
    }
}
