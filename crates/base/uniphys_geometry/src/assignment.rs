//! Exact rectangular assignment (Kuhn-Munkres with potentials, shortest augmenting paths,
//! O(n^2 m) for n <= m).

use crate::{GeometryError, GeometryResult};

/// The assignment of rows to columns that minimises the total cost, for a row-major
/// `rows x cols` matrix: `min(rows, cols)` pairs, every row and column used at most once.
/// Returns the column of every row (`None` for rows left over when `rows > cols`).
///
/// Costs must be finite. Ties are broken deterministically.
pub fn min_cost_assignment(
    cost: &[f64],
    rows: usize,
    cols: usize,
) -> GeometryResult<Vec<Option<usize>>> {
    if cost.len() != rows * cols {
        return Err(GeometryError::InvalidParameter(format!(
            "{} costs for a {rows} x {cols} matrix",
            cost.len()
        )));
    }
    if cost.iter().any(|c| !c.is_finite()) {
        return Err(GeometryError::InvalidParameter(
            "an assignment cost is not finite".into(),
        ));
    }
    if rows == 0 || cols == 0 {
        return Ok(vec![None; rows]);
    }
    if rows <= cols {
        Ok(solve(|i, j| cost[i * cols + j], rows, cols)
            .into_iter()
            .map(Some)
            .collect())
    } else {
        // Transposed: every column gets a row.
        let row_of_col = solve(|i, j| cost[j * cols + i], cols, rows);
        let mut out = vec![None; rows];
        for (col, row) in row_of_col.into_iter().enumerate() {
            out[row] = Some(col);
        }
        Ok(out)
    }
}

/// Total cost of an assignment from [`min_cost_assignment`].
#[must_use]
pub fn assignment_cost(cost: &[f64], cols: usize, assignment: &[Option<usize>]) -> f64 {
    assignment
        .iter()
        .enumerate()
        .filter_map(|(i, j)| j.map(|j| cost[i * cols + j]))
        .sum()
}

/// n <= m; returns the column of every row.
fn solve(a: impl Fn(usize, usize) -> f64, n: usize, m: usize) -> Vec<usize> {
    // 1-based rows and columns; column 0 is the virtual start of each augmenting path.
    let mut u = vec![0.0f64; n + 1];
    let mut v = vec![0.0f64; m + 1];
    let mut row_of = vec![0usize; m + 1];
    let mut way = vec![0usize; m + 1];
    for i in 1..=n {
        row_of[0] = i;
        let mut j0 = 0;
        let mut min_v = vec![f64::INFINITY; m + 1];
        let mut used = vec![false; m + 1];
        loop {
            used[j0] = true;
            let i0 = row_of[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0;
            for j in 1..=m {
                if used[j] {
                    continue;
                }
                let reduced = a(i0 - 1, j - 1) - u[i0] - v[j];
                if reduced < min_v[j] {
                    min_v[j] = reduced;
                    way[j] = j0;
                }
                if min_v[j] < delta {
                    delta = min_v[j];
                    j1 = j;
                }
            }
            for j in 0..=m {
                if used[j] {
                    u[row_of[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_v[j] -= delta;
                }
            }
            j0 = j1;
            if row_of[j0] == 0 {
                break;
            }
        }
        loop {
            let j1 = way[j0];
            row_of[j0] = row_of[j1];
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    let mut col_of = vec![0usize; n];
    for j in 1..=m {
        if row_of[j] != 0 {
            col_of[row_of[j] - 1] = j - 1;
        }
    }
    col_of
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// Smallest total over every way to give each of min(rows, cols) rows a distinct column.
    fn brute_force(cost: &[f64], rows: usize, cols: usize) -> f64 {
        fn go(
            cost: &[f64],
            rows: usize,
            cols: usize,
            i: usize,
            used: &mut [bool],
            left: usize,
        ) -> f64 {
            if left == 0 {
                return 0.0;
            }
            if rows - i < left {
                return f64::INFINITY;
            }
            // Row i unassigned (only possible when rows > cols).
            let mut best = if rows - i > left {
                go(cost, rows, cols, i + 1, used, left)
            } else {
                f64::INFINITY
            };
            for j in 0..cols {
                if !used[j] {
                    used[j] = true;
                    best =
                        best.min(cost[i * cols + j] + go(cost, rows, cols, i + 1, used, left - 1));
                    used[j] = false;
                }
            }
            best
        }
        go(cost, rows, cols, 0, &mut vec![false; cols], rows.min(cols))
    }

    fn check(cost: &[f64], rows: usize, cols: usize) {
        let assignment = min_cost_assignment(cost, rows, cols).unwrap();
        assert_eq!(assignment.len(), rows);
        let assigned: Vec<usize> = assignment.iter().flatten().copied().collect();
        assert_eq!(assigned.len(), rows.min(cols));
        let mut distinct = assigned.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), assigned.len());
        let total = assignment_cost(cost, cols, &assignment);
        let best = brute_force(cost, rows, cols);
        assert!((total - best).abs() < 1e-9, "{total} vs {best}");
    }

    #[test]
    fn hand_checked_square_and_rectangular_cases() {
        // The greedy choice (row 0 -> col 0) is wrong here: optimum 1 + 2 = 3.
        let cost = [1.0, 2.0, 1.0, 10.0];
        assert_eq!(
            min_cost_assignment(&cost, 2, 2).unwrap(),
            vec![Some(1), Some(0)]
        );
        // Three rows, one column: the cheapest row takes it.
        assert_eq!(
            min_cost_assignment(&[0.5, 0.2, 0.9], 3, 1).unwrap(),
            vec![None, Some(0), None]
        );
        assert_eq!(min_cost_assignment(&[], 0, 3).unwrap(), vec![]);
        assert!(min_cost_assignment(&[f64::NAN], 1, 1).is_err());
        assert!(min_cost_assignment(&[1.0], 1, 2).is_err());
    }

    proptest! {
        #[test]
        fn matches_brute_force_on_small_random_matrices(
            rows in 1usize..6,
            cols in 1usize..6,
            values in proptest::collection::vec(0u32..20, 36),
        ) {
            let cost: Vec<f64> = values[..rows * cols].iter().map(|&v| f64::from(v) / 4.0).collect();
            check(&cost, rows, cols);
        }
    }
}
