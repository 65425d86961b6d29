//! The part-count prior K0 from the merged masks (reference §3.5 step 2) and the range of part
//! counts the candidates are asked for.

use std::ops::RangeInclusive;

use crate::lift::FaceSet;

/// Fraction of the visible surface the largest masks must exceed to set K0 (the reference's
/// 0.99).
pub const K_PRIOR_COVERAGE: f64 = 0.99;

/// K0: the number of largest masks (by surface area) needed to cover more than `coverage` of the
/// area of all faces in any mask.
///
/// Masks are taken largest first (ties: input order); a mask is counted while the area covered
/// before it is at most `coverage` of the total, as in the reference. Faces counted by several
/// masks count once per mask (the masks of [`crate::consensus::merge_masks`] are disjoint). 0 when
/// there are no masks; at least 1 otherwise, also when every face has zero area.
#[must_use]
pub fn k_prior(masks: &[FaceSet], face_area_m2: &[f64], coverage: f64) -> usize {
    let area = |f: &u32| face_area_m2.get(*f as usize).copied().unwrap_or(0.0);
    let mut areas: Vec<(f64, usize)> = masks
        .iter()
        .enumerate()
        .filter(|(_, m)| !m.is_empty())
        .map(|(i, m)| (m.iter().map(area).sum(), i))
        .collect();
    if areas.is_empty() {
        return 0;
    }
    let mut visible: Vec<u32> = masks.iter().flatten().copied().collect();
    visible.sort_unstable();
    visible.dedup();
    let surface_m2: f64 = visible.iter().map(area).sum();
    if surface_m2 <= 0.0 {
        return 1;
    }
    areas.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut covered_m2 = 0.0;
    let mut k = 0;
    for (a, _) in areas {
        if covered_m2 / surface_m2 > coverage {
            break;
        }
        covered_m2 += a;
        k += 1;
    }
    k
}

/// The part counts to try around the prior: `max(1, k_prior - below) ..= k_prior + above`,
/// capped at `face_count` (a mesh cannot have more parts than faces) and never empty.
///
/// The reference states the range as K0 - 3 ... K0 + 14 (`below` 3, `above` 14); its Python
/// `range` actually stops at K0 + 13. We include `k_prior + above`, as stated.
#[must_use]
pub fn k_range(
    k_prior: usize,
    below: usize,
    above: usize,
    face_count: usize,
) -> RangeInclusive<usize> {
    let end = k_prior.saturating_add(above).min(face_count).max(1);
    let start = k_prior.saturating_sub(below).max(1).min(end);
    start..=end
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn k_prior_counts_the_largest_masks_needed_to_exceed_the_coverage() {
        // Areas 50, 30, 15, 4, 1 of 100: 99 % is reached only with the fifth mask, but the
        // covered share is checked before adding one: 0.5, 0.8, 0.95, 0.99 (not > 0.99) -> 5.
        let area: Vec<f64> = vec![50.0, 30.0, 15.0, 4.0, 1.0];
        let masks: Vec<FaceSet> = vec![vec![3], vec![0], vec![4], vec![2], vec![1]];
        assert_eq!(k_prior(&masks, &area, K_PRIOR_COVERAGE), 5);
        // With 95 % coverage: 0.5, 0.8, 0.95 (not > 0.95), 0.99 > 0.95 stop -> 4.
        assert_eq!(k_prior(&masks, &area, 0.95), 4);
        // With 90 %: stop after 50 + 30 + 15 -> 3.
        assert_eq!(k_prior(&masks, &area, 0.9), 3);
        // A mask of tiny faces does not count once the rest covers the surface.
        let area = vec![60.0, 39.9, 0.05, 0.05];
        let masks: Vec<FaceSet> = vec![vec![0], vec![1], vec![2], vec![3]];
        assert_eq!(k_prior(&masks, &area, K_PRIOR_COVERAGE), 2);
        assert_eq!(k_prior(&[], &area, K_PRIOR_COVERAGE), 0);
    }

    #[test]
    fn k_range_spans_the_prior_and_stays_within_the_face_count() {
        assert_eq!(k_range(5, 3, 14, 1000), 2..=19);
        assert_eq!(k_range(2, 3, 14, 1000), 1..=16);
        assert_eq!(k_range(5, 3, 14, 8), 2..=8);
        assert_eq!(k_range(0, 3, 14, 0), 1..=1);
        assert_eq!(k_range(30, 3, 14, 12), 12..=12);
    }
}
