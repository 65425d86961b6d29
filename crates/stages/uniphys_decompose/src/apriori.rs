//! Merge groups of parts mined across views (reference §3.6b, without its off-by-one and with a
//! budget on the number of itemsets instead of wall time).
//!
//! Every mask of every view is a transaction: the parts that lie mostly (coverage >= 0.5 of the
//! part's area seen in that view) inside the mask. Itemsets found in at least `min_support`
//! transactions (Apriori, level by level) are kept when maximal, ordered by length then support,
//! and merged greedily when they overlap enough; parts in one group become one part. Too many
//! parts or itemsets fall back to the "normal merge": parts covered by the same cross-view mask
//! are merged.

use std::collections::BTreeSet;

use crate::candidates::relabel_by_first_face;

/// Tuning of [`merge_parts`].
#[derive(Debug, Clone, PartialEq)]
pub struct AprioriOptions {
    /// A part belongs to a mask when at least this share of its visible area is in it. Default 0.5.
    pub coverage_min: f64,
    /// Transactions an itemset must appear in. Default 3.
    pub min_support: usize,
    /// Candidate itemsets counted at most; beyond it the normal merge is used. Default 100 000.
    pub itemset_budget: usize,
    /// Groups merge when their area IoU exceeds this. Default 0.2.
    pub merge_iou: f64,
    /// ... or when their intersection exceeds this share of the smaller group. Default 0.5.
    pub merge_overlap: f64,
    /// With more parts than this the normal merge is used. Default 100.
    pub max_parts: usize,
    /// Drop itemsets whose parts some views show in different masks as often as views show them
    /// together (the reference merges on co-occurrence alone). Default true.
    pub require_consistency: bool,
}

impl Default for AprioriOptions {
    fn default() -> Self {
        Self {
            coverage_min: 0.5,
            min_support: 3,
            itemset_budget: 100_000,
            merge_iou: 0.2,
            merge_overlap: 0.5,
            max_parts: 100,
            require_consistency: true,
        }
    }
}

/// The result of [`merge_parts`].
#[derive(Debug, Clone, PartialEq)]
pub struct MergeOutcome {
    /// Part of every face, `0..part_count`, numbered by smallest face.
    pub face_part: Vec<u32>,
    /// Number of parts.
    pub part_count: usize,
    /// "apriori merge", "normal merge selected for N parts" or "apriori itemset budget exceeded;
    /// used normal merge".
    pub strategy: String,
    /// Transactions mined (0 for the normal merge).
    pub transactions: usize,
}

/// Merges parts that the masks show together: Apriori over per-view masks, or the normal merge
/// over the cross-view `merged_masks` when there are too many parts or itemsets.
#[must_use]
pub fn merge_parts(
    face_part: &[u32],
    per_view: &[Vec<Vec<u32>>],
    merged_masks: &[Vec<u32>],
    face_area_m2: &[f64],
    options: &AprioriOptions,
) -> MergeOutcome {
    let parts = face_part.iter().max().map_or(0, |&m| m as usize + 1);
    let mut part_area = vec![0.0f64; parts];
    for (f, &p) in face_part.iter().enumerate() {
        part_area[p as usize] += face_area_m2[f];
    }
    if parts > options.max_parts {
        let merged = normal_merge(face_part, parts, merged_masks, face_area_m2, options);
        return finish(
            face_part,
            &merged,
            format!("normal merge selected for {parts} parts"),
            0,
        );
    }
    let by_view: Vec<Vec<Vec<u32>>> = per_view
        .iter()
        .map(|masks| assigned_parts(face_part, parts, masks, face_area_m2, options))
        .collect();
    let transactions: Vec<Vec<u32>> = by_view
        .iter()
        .flatten()
        .filter(|t| !t.is_empty())
        .cloned()
        .collect();
    let Some(itemsets) =
        frequent_itemsets(&transactions, options.min_support, options.itemset_budget)
    else {
        let merged = normal_merge(face_part, parts, merged_masks, face_area_m2, options);
        return finish(
            face_part,
            &merged,
            "apriori itemset budget exceeded; used normal merge".to_owned(),
            transactions.len(),
        );
    };
    let itemsets = if options.require_consistency {
        consistent(itemsets, &by_view, parts)
    } else {
        itemsets
    };
    let groups = greedy_groups(maximal(itemsets), &part_area, options);
    let mut group_of = vec![u32::MAX; parts];
    for (g, group) in groups.iter().enumerate() {
        for &p in group {
            if group_of[p as usize] == u32::MAX {
                group_of[p as usize] = u32::try_from(g).unwrap_or(u32::MAX);
            }
        }
    }
    let mut next = u32::try_from(groups.len()).unwrap_or(u32::MAX);
    for g in &mut group_of {
        if *g == u32::MAX {
            *g = next;
            next += 1;
        }
    }
    finish(
        face_part,
        &group_of,
        "apriori merge".to_owned(),
        transactions.len(),
    )
}

fn finish(
    face_part: &[u32],
    new_of_part: &[u32],
    strategy: String,
    transactions: usize,
) -> MergeOutcome {
    let labels: Vec<u32> = face_part.iter().map(|&p| new_of_part[p as usize]).collect();
    let (face_part, part_count) = relabel_by_first_face(&labels);
    MergeOutcome {
        face_part,
        part_count,
        strategy,
        transactions,
    }
}

/// For each mask, the parts assigned to it: the parts whose area within `masks` is mostly inside
/// it (best mask, first on ties). Sorted part ids per mask.
fn assigned_parts(
    face_part: &[u32],
    parts: usize,
    masks: &[Vec<u32>],
    face_area_m2: &[f64],
    options: &AprioriOptions,
) -> Vec<Vec<u32>> {
    let mut seen_area = vec![0.0f64; parts];
    let mut counted = vec![false; face_part.len()];
    let mut inter = vec![0.0f64; masks.len() * parts];
    for (i, mask) in masks.iter().enumerate() {
        for &f in mask {
            let (p, a) = (face_part[f as usize] as usize, face_area_m2[f as usize]);
            inter[i * parts + p] += a;
            if !counted[f as usize] {
                counted[f as usize] = true;
                seen_area[p] += a;
            }
        }
    }
    let mut out = vec![Vec::new(); masks.len()];
    for p in 0..parts {
        if seen_area[p] <= 0.0 {
            continue;
        }
        let mut best: Option<(usize, f64)> = None;
        for i in 0..masks.len() {
            let coverage = inter[i * parts + p] / seen_area[p];
            if coverage >= options.coverage_min && best.is_none_or(|(_, c)| coverage > c) {
                best = Some((i, coverage));
            }
        }
        if let Some((i, _)) = best {
            out[i].push(u32::try_from(p).unwrap_or(u32::MAX));
        }
    }
    out
}

/// Parts assigned to the same cross-view mask become one part; returns the new id of every part.
fn normal_merge(
    face_part: &[u32],
    parts: usize,
    merged_masks: &[Vec<u32>],
    face_area_m2: &[f64],
    options: &AprioriOptions,
) -> Vec<u32> {
    let assigned = assigned_parts(face_part, parts, merged_masks, face_area_m2, options);
    let mut new_of_part: Vec<u32> = (0..u32::try_from(parts).unwrap_or(u32::MAX)).collect();
    for group in assigned {
        if let Some(&first) = group.first() {
            for &p in &group {
                new_of_part[p as usize] = first;
            }
        }
    }
    new_of_part
}

/// Frequent itemsets with their support, or `None` past the budget of candidate itemsets.
fn frequent_itemsets(
    transactions: &[Vec<u32>],
    min_support: usize,
    budget: usize,
) -> Option<Vec<(Vec<u32>, usize)>> {
    let min_support = min_support.max(1);
    let mut counted = 0usize;
    let mut all = Vec::new();
    let mut items: Vec<u32> = transactions.iter().flatten().copied().collect();
    items.sort_unstable();
    items.dedup();
    let mut level: Vec<Vec<u32>> = items.into_iter().map(|i| vec![i]).collect();
    while !level.is_empty() {
        counted += level.len();
        if counted > budget {
            return None;
        }
        let frequent: Vec<(Vec<u32>, usize)> = level
            .into_iter()
            .map(|set| {
                let support = transactions.iter().filter(|t| is_subset(&set, t)).count();
                (set, support)
            })
            .filter(|(_, s)| *s >= min_support)
            .collect();
        let known: BTreeSet<&Vec<u32>> = frequent.iter().map(|(s, _)| s).collect();
        // Join sets sharing all but the last item; keep candidates whose subsets are frequent.
        let mut next = Vec::new();
        for (i, (a, _)) in frequent.iter().enumerate() {
            for (b, _) in &frequent[i + 1..] {
                let k = a.len();
                if a[..k - 1] != b[..k - 1] {
                    break;
                }
                let mut joined = a.clone();
                joined.push(b[k - 1]);
                let all_frequent = (0..joined.len()).all(|skip| {
                    let subset: Vec<u32> = joined
                        .iter()
                        .enumerate()
                        .filter(|&(j, _)| j != skip)
                        .map(|(_, &x)| x)
                        .collect();
                    known.contains(&subset)
                });
                if all_frequent {
                    next.push(joined);
                }
            }
        }
        all.extend(frequent);
        level = next;
    }
    Some(all)
}

/// The itemsets that views show together (support) more often than apart: a view shows a set
/// apart when its parts are assigned to two or more different masks of the view.
fn consistent(
    itemsets: Vec<(Vec<u32>, usize)>,
    by_view: &[Vec<Vec<u32>>],
    parts: usize,
) -> Vec<(Vec<u32>, usize)> {
    // Mask of every part in every view (u32::MAX: not assigned).
    let mask_of: Vec<Vec<u32>> = by_view
        .iter()
        .map(|masks| {
            let mut of = vec![u32::MAX; parts];
            for (m, members) in masks.iter().enumerate() {
                for &p in members {
                    of[p as usize] = u32::try_from(m).unwrap_or(u32::MAX);
                }
            }
            of
        })
        .collect();
    itemsets
        .into_iter()
        .filter(|(set, support)| {
            if set.len() < 2 {
                return true;
            }
            let apart = mask_of
                .iter()
                .filter(|of| {
                    let mut seen: Vec<u32> = set
                        .iter()
                        .map(|&p| of[p as usize])
                        .filter(|&m| m != u32::MAX)
                        .collect();
                    seen.sort_unstable();
                    seen.dedup();
                    seen.len() >= 2
                })
                .count();
            apart < *support
        })
        .collect()
}

/// Whether sorted `a` is a subset of sorted `b`.
fn is_subset(a: &[u32], b: &[u32]) -> bool {
    let mut j = 0;
    for &x in a {
        while j < b.len() && b[j] < x {
            j += 1;
        }
        if j == b.len() || b[j] != x {
            return false;
        }
        j += 1;
    }
    true
}

/// Itemsets ordered by length (longest first), then support (highest first), then items; those
/// inside an already kept one are dropped.
fn maximal(mut itemsets: Vec<(Vec<u32>, usize)>) -> Vec<Vec<u32>> {
    itemsets.sort_by(|(a, sa), (b, sb)| b.len().cmp(&a.len()).then(sb.cmp(sa)).then(a.cmp(b)));
    let mut kept: Vec<Vec<u32>> = Vec::new();
    for (set, _) in itemsets {
        if !kept.iter().any(|k| is_subset(&set, k)) {
            kept.push(set);
        }
    }
    kept
}

/// One greedy pass: each unused set absorbs every later unused set that overlaps it enough;
/// a smaller overlap is removed from the smaller-area set.
fn greedy_groups(
    mut sets: Vec<Vec<u32>>,
    part_area: &[f64],
    options: &AprioriOptions,
) -> Vec<Vec<u32>> {
    let area = |s: &[u32]| s.iter().map(|&p| part_area[p as usize]).sum::<f64>();
    let mut used = vec![false; sets.len()];
    for i in 0..sets.len() {
        if used[i] {
            continue;
        }
        for j in i + 1..sets.len() {
            if used[j] {
                continue;
            }
            let inter: Vec<u32> = sets[i]
                .iter()
                .filter(|p| sets[j].binary_search(p).is_ok())
                .copied()
                .collect();
            if inter.is_empty() {
                continue;
            }
            let (ai, aj, ax) = (area(&sets[i]), area(&sets[j]), area(&inter));
            let union = ai + aj - ax;
            let iou = if union > 0.0 { ax / union } else { 0.0 };
            let smaller = ai.min(aj);
            let overlap = if smaller > 0.0 { ax / smaller } else { 0.0 };
            if iou > options.merge_iou || overlap > options.merge_overlap {
                let absorbed = std::mem::take(&mut sets[j]);
                sets[i].extend(absorbed);
                sets[i].sort_unstable();
                sets[i].dedup();
                used[j] = true;
            } else if aj <= ai {
                sets[j].retain(|p| inter.binary_search(p).is_err());
            } else {
                sets[i].retain(|p| inter.binary_search(p).is_err());
            }
        }
    }
    sets.into_iter()
        .zip(used)
        .filter(|(s, u)| !u && !s.is_empty())
        .map(|(s, _)| s)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apriori_finds_frequent_pairs_and_keeps_maximal_sets() {
        let transactions = vec![
            vec![0, 1, 2],
            vec![0, 1],
            vec![0, 1, 3],
            vec![2, 3],
            vec![2, 3],
            vec![2, 3, 4],
        ];
        let sets = frequent_itemsets(&transactions, 3, 1000).unwrap();
        let support = |s: &[u32]| sets.iter().find(|(x, _)| x == s).map(|(_, n)| *n);
        assert_eq!(support(&[0, 1]), Some(3));
        assert_eq!(support(&[2, 3]), Some(3));
        assert_eq!(support(&[0, 1, 2]), None);
        assert_eq!(support(&[4]), None);
        assert_eq!(maximal(sets), vec![vec![0, 1], vec![2, 3]]);
        // A budget smaller than the first level gives up.
        assert!(frequent_itemsets(&transactions, 3, 3).is_none());
    }

    #[test]
    fn parts_seen_together_in_three_views_are_merged() {
        // Six faces of unit area, one per part; parts 0 and 1 appear in one mask in 3 views,
        // part 2 alone; parts 3..6 never together three times.
        let face_part: Vec<u32> = (0..6).collect();
        let areas = vec![1.0; 6];
        let per_view = vec![
            vec![vec![0, 1], vec![2], vec![3, 4]],
            vec![vec![0, 1], vec![2, 5]],
            vec![vec![0, 1, 2]],
            vec![vec![0, 1], vec![4, 5]],
        ];
        let outcome = merge_parts(
            &face_part,
            &per_view,
            &[],
            &areas,
            &AprioriOptions::default(),
        );
        assert_eq!(outcome.strategy, "apriori merge");
        assert_eq!(outcome.face_part, vec![0, 0, 1, 2, 3, 4]);
        assert_eq!(outcome.part_count, 5);
    }

    #[test]
    fn overlapping_groups_merge_by_area_without_off_by_one() {
        // Parts 0 (area 10) in both sets: inter/min = 10 / 11 > 0.5 -> merged.
        let areas = [10.0, 1.0, 1.0];
        let groups = greedy_groups(
            vec![vec![0, 1], vec![0, 2]],
            &areas,
            &AprioriOptions::default(),
        );
        assert_eq!(groups, vec![vec![0, 1, 2]]);
        // Small shared part 0 (area 1) between two big ones: removed from the smaller set.
        let areas = [1.0, 10.0, 8.0];
        let groups = greedy_groups(
            vec![vec![0, 1], vec![0, 2]],
            &areas,
            &AprioriOptions::default(),
        );
        assert_eq!(groups, vec![vec![0, 1], vec![2]]);
    }

    #[test]
    fn parts_that_other_views_show_apart_are_not_merged() {
        // Parts 0 and 1 share a mask in 3 views but are in different masks in 3 others.
        let face_part: Vec<u32> = (0..3).collect();
        let areas = vec![1.0; 3];
        let together = vec![vec![0, 1], vec![2]];
        let apart = vec![vec![0], vec![1], vec![2]];
        let per_view = vec![
            together.clone(),
            together.clone(),
            together,
            apart.clone(),
            apart.clone(),
            apart,
        ];
        let outcome = merge_parts(
            &face_part,
            &per_view,
            &[],
            &areas,
            &AprioriOptions::default(),
        );
        assert_eq!(outcome.part_count, 3);
        // The reference's rule (co-occurrence alone) merges them.
        let reference = AprioriOptions {
            require_consistency: false,
            ..AprioriOptions::default()
        };
        let outcome = merge_parts(&face_part, &per_view, &[], &areas, &reference);
        assert_eq!(outcome.face_part, vec![0, 0, 1]);
    }

    #[test]
    fn too_many_parts_use_the_normal_merge() {
        let face_part: Vec<u32> = (0..4).collect();
        let areas = vec![1.0; 4];
        let options = AprioriOptions {
            max_parts: 3,
            ..AprioriOptions::default()
        };
        let merged = vec![vec![0, 1], vec![2, 3]];
        let outcome = merge_parts(&face_part, &[], &merged, &areas, &options);
        assert_eq!(outcome.face_part, vec![0, 0, 1, 1]);
        assert_eq!(outcome.strategy, "normal merge selected for 4 parts");
    }
}
