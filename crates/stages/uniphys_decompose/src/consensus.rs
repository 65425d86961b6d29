//! Cross-view merging of the lifted masks (reference §3.3): masks that cover the same surface in
//! different views become one, by union-find over area-weighted overlaps, pass after pass.

use std::collections::BTreeMap;

use crate::candidates::UnionFind;
use crate::lift::FaceSet;

/// Options of [`merge_masks`] and [`merge_view_masks`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConsensusOptions {
    /// Two masks merge when their area-weighted IoU is at least this (default 0.2).
    pub iou_min: f64,
    /// ... or when their overlap coefficient, intersection over the smaller area, exceeds this
    /// (default 0.9).
    pub overlap_min: f64,
    /// Merge passes at most; merging stops earlier once a pass changes nothing (default 10).
    pub max_passes: usize,
    /// [`merge_view_masks`] only: two masks that share faces also merge when their IoU counted
    /// on the faces both masks' views saw reaches this (default 0.5; above 1 switches it off).
    pub co_visible_iou_min: f64,
}

impl Default for ConsensusOptions {
    fn default() -> Self {
        Self {
            iou_min: 0.2,
            overlap_min: 0.9,
            max_passes: 10,
            co_visible_iou_min: 0.5,
        }
    }
}

/// Masks (of all views) that the pairwise intersections are kept for in a dense matrix; beyond,
/// a sorted map.
const DENSE_PAIR_LIMIT: usize = 1024;

/// A merged mask: its faces with the number of input masks that contain each.
#[derive(Debug, Clone, Default)]
struct Group {
    /// `(face, votes)`, sorted by face.
    faces: Vec<(u32, u32)>,
    area_m2: f64,
    /// Bit `v % 64` set for every view `v` that contributed a mask.
    views: u64,
}

/// Merges the lifted masks of all views into disjoint face sets.
///
/// Each pass unions (union-find, so merging is transitive within a pass) every two masks whose
/// area-weighted IoU reaches [`ConsensusOptions::iou_min`] or whose intersection exceeds
/// [`ConsensusOptions::overlap_min`] of the smaller one; the unions are the next pass's masks.
/// Passes stop when one merges nothing. Masks that were not merged may still share faces; such a
/// face goes to the merged mask with the most votes for it (the number of input masks containing
/// it, i.e. of views that gave it to that mask); on equal votes to the smaller mask by area (the
/// more specific one: a view that separated a part outweighs one that missed the boundary, as
/// smaller masks overwrite larger ones in the reference's label maps), then to the earlier one.
/// The result is sorted by area, largest first (ties: smaller first face); empty masks are left
/// out. Faces beyond `face_area_m2` are ignored.
#[must_use]
pub fn merge_masks(
    masks: &[FaceSet],
    face_area_m2: &[f64],
    options: &ConsensusOptions,
) -> Vec<FaceSet> {
    let masks: Vec<(u64, &FaceSet)> = masks.iter().map(|m| (0, m)).collect();
    merge(&masks, face_area_m2, &[], options)
}

/// [`merge_masks`] over the masks of every view (`per_view[v]`, disjoint within a view), with
/// one more reason to merge: two masks that share faces and whose IoU, counted only on faces
/// that both masks' views saw (lifted to any mask there), reaches
/// [`ConsensusOptions::co_visible_iou_min`]. The two sides of a thin part (a lid, a laptop
/// base) are seen by disjoint views and share only their rim: their plain IoU is small, but
/// on the faces both sets of views saw (the rim) they agree. Views beyond 64 share view bits.
#[must_use]
pub fn merge_view_masks(
    per_view: &[Vec<FaceSet>],
    face_area_m2: &[f64],
    options: &ConsensusOptions,
) -> Vec<FaceSet> {
    let mut visible = vec![0u64; face_area_m2.len()];
    let mut masks: Vec<(u64, &FaceSet)> = Vec::new();
    for (v, view_masks) in per_view.iter().enumerate() {
        let bit = 1u64 << (v % 64);
        for mask in view_masks {
            for &f in mask {
                if let Some(bits) = visible.get_mut(f as usize) {
                    *bits |= bit;
                }
            }
            masks.push((bit, mask));
        }
    }
    merge(&masks, face_area_m2, &visible, options)
}

/// The passes and the final face assignment; `visible` (per face, the bits of the views that
/// saw it) is empty without view information.
fn merge(
    masks: &[(u64, &FaceSet)],
    face_area_m2: &[f64],
    visible: &[u64],
    options: &ConsensusOptions,
) -> Vec<FaceSet> {
    let area = |f: u32| face_area_m2.get(f as usize).copied().unwrap_or(0.0);
    let mut groups: Vec<Group> = masks
        .iter()
        .map(|&(views, mask)| {
            let mut faces: Vec<(u32, u32)> = mask
                .iter()
                .filter(|&&f| (f as usize) < face_area_m2.len())
                .map(|&f| (f, 1))
                .collect();
            faces.sort_unstable();
            faces.dedup();
            let area_m2 = faces.iter().map(|&(f, _)| area(f)).sum();
            Group {
                faces,
                area_m2,
                views,
            }
        })
        .filter(|g| !g.faces.is_empty())
        .collect();

    for _ in 0..options.max_passes {
        let merged = merge_pass(&groups, &area, visible, options);
        if merged.len() == groups.len() {
            break;
        }
        groups = merged;
    }
    disjoint_face_sets(&groups, face_area_m2)
}

/// One union-find pass; returns the groups unchanged in number when nothing merged.
fn merge_pass(
    groups: &[Group],
    area: &dyn Fn(u32) -> f64,
    visible: &[u64],
    options: &ConsensusOptions,
) -> Vec<Group> {
    let n = groups.len();
    let mut members: Vec<(u32, u32)> = groups
        .iter()
        .enumerate()
        .flat_map(|(g, group)| {
            let g = u32::try_from(g).unwrap_or(u32::MAX);
            group.faces.iter().map(move |&(f, _)| (f, g))
        })
        .collect();
    members.sort_unstable();

    let mut dense = if n <= DENSE_PAIR_LIMIT {
        vec![0.0f64; n * n]
    } else {
        Vec::new()
    };
    let mut sparse: BTreeMap<(u32, u32), f64> = BTreeMap::new();
    for same_face in members.chunk_by(|a, b| a.0 == b.0) {
        let a_f = area(same_face[0].0);
        for (k, &(_, i)) in same_face.iter().enumerate() {
            for &(_, j) in &same_face[k + 1..] {
                if dense.is_empty() {
                    *sparse.entry((i, j)).or_insert(0.0) += a_f;
                } else {
                    dense[i as usize * n + j as usize] += a_f;
                }
            }
        }
    }
    let pairs: Box<dyn Iterator<Item = ((u32, u32), f64)>> = if dense.is_empty() {
        Box::new(sparse.into_iter())
    } else {
        Box::new(
            dense
                .iter()
                .enumerate()
                .filter(|&(_, &a)| a > 0.0)
                .map(|(k, &a)| {
                    let (i, j) = (k / n, k % n);
                    ((i as u32, j as u32), a)
                }),
        )
    };

    let mut uf = UnionFind::new(n);
    let mut unions = 0usize;
    for ((i, j), inter) in pairs {
        let (a_i, a_j) = (groups[i as usize].area_m2, groups[j as usize].area_m2);
        let union = a_i + a_j - inter;
        let smaller = a_i.min(a_j);
        let iou = if union > 0.0 { inter / union } else { 0.0 };
        let overlap = if smaller > 0.0 { inter / smaller } else { 0.0 };
        let merge = iou >= options.iou_min
            || overlap > options.overlap_min
            || (!visible.is_empty()
                && co_visible_iou(
                    &groups[i as usize],
                    &groups[j as usize],
                    inter,
                    area,
                    visible,
                ) >= options.co_visible_iou_min);
        if merge && uf.union(i, j) {
            unions += 1;
        }
    }
    if unions == 0 {
        return groups.to_vec();
    }

    // Components in the order of their smallest member (the union-find root).
    let mut component_faces: BTreeMap<u32, (Vec<(u32, u32)>, u64)> = BTreeMap::new();
    for (g, group) in groups.iter().enumerate() {
        let root = uf.find(u32::try_from(g).unwrap_or(u32::MAX));
        let entry = component_faces.entry(root).or_default();
        entry.0.extend_from_slice(&group.faces);
        entry.1 |= group.views;
    }
    component_faces
        .into_values()
        .map(|(mut faces, views)| {
            faces.sort_unstable();
            let mut summed: Vec<(u32, u32)> = Vec::with_capacity(faces.len());
            for (f, votes) in faces {
                match summed.last_mut() {
                    Some(last) if last.0 == f => last.1 += votes,
                    _ => summed.push((f, votes)),
                }
            }
            let area_m2 = summed.iter().map(|&(f, _)| area(f)).sum();
            Group {
                faces: summed,
                area_m2,
                views,
            }
        })
        .collect()
}

/// IoU of two groups sharing `inter_m2` of area, counted on the faces seen by views of both: a
/// shared face was seen by both (it is in both), a face of one group counts when a view of the
/// other saw it.
fn co_visible_iou(
    a: &Group,
    b: &Group,
    inter_m2: f64,
    area: &dyn Fn(u32) -> f64,
    visible: &[u64],
) -> f64 {
    let seen_by = |group: &Group, views: u64| -> f64 {
        group
            .faces
            .iter()
            .filter(|&&(f, _)| {
                visible
                    .get(f as usize)
                    .is_some_and(|&bits| bits & views != 0)
            })
            .map(|&(f, _)| area(f))
            .sum()
    };
    let union = seen_by(a, b.views) + seen_by(b, a.views) - inter_m2;
    if union > 0.0 { inter_m2 / union } else { 0.0 }
}

/// Gives every face to one group (most votes, then smaller area, then earlier group) and sorts
/// the resulting sets by area, largest first.
fn disjoint_face_sets(groups: &[Group], face_area_m2: &[f64]) -> Vec<FaceSet> {
    let mut owner: Vec<(u32, u32)> = vec![(u32::MAX, 0); face_area_m2.len()];
    for (g, group) in groups.iter().enumerate() {
        let g = u32::try_from(g).unwrap_or(u32::MAX);
        for &(f, votes) in &group.faces {
            let slot = &mut owner[f as usize];
            let better = slot.0 == u32::MAX
                || votes > slot.1
                || (votes == slot.1 && group.area_m2 < groups[slot.0 as usize].area_m2);
            if better {
                *slot = (g, votes);
            }
        }
    }
    let mut sets: Vec<(f64, FaceSet)> = vec![(0.0, Vec::new()); groups.len()];
    for (f, &(g, _)) in owner.iter().enumerate() {
        if g != u32::MAX {
            sets[g as usize]
                .1
                .push(u32::try_from(f).unwrap_or(u32::MAX));
        }
    }
    for set in &mut sets {
        set.0 = set.1.iter().map(|&f| face_area_m2[f as usize]).sum();
    }
    let mut sets: Vec<(f64, FaceSet)> = sets.into_iter().filter(|(_, s)| !s.is_empty()).collect();
    sets.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1[0].cmp(&b.1[0])));
    sets.into_iter().map(|(_, s)| s).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn range(r: std::ops::Range<u32>) -> FaceSet {
        r.collect()
    }

    #[test]
    fn the_same_part_seen_in_different_views_becomes_one_mask() {
        // View 0 sees faces 0..6 of the body and the lid 10..12; view 1 sees 3..9 of the body and
        // the lid 10..13; view 2 sees only the body's 0..9.
        let masks = vec![
            range(0..6),
            range(10..12),
            range(3..9),
            range(10..13),
            range(0..9),
        ];
        let merged = merge_masks(&masks, &[1.0; 13], &ConsensusOptions::default());
        assert_eq!(merged, vec![range(0..9), range(10..13)]);
    }

    #[test]
    fn overlap_is_measured_by_area_not_face_count() {
        // The shared face 3 is large: IoU 10 / 16 by area (merged), 1 / 7 by face count.
        let masks = vec![range(0..4), range(3..7)];
        let mut area = vec![1.0; 7];
        area[3] = 10.0;
        let merged = merge_masks(&masks, &area, &ConsensusOptions::default());
        assert_eq!(merged, vec![range(0..7)]);
        let merged = merge_masks(&masks, &[1.0; 7], &ConsensusOptions::default());
        assert_eq!(merged.len(), 2);
    }

    #[test]
    fn a_mask_inside_another_merges_by_the_overlap_coefficient() {
        // IoU 3 / 20 is below 0.2, but all of the small mask lies in the large one.
        let masks = vec![range(0..20), range(5..8)];
        let merged = merge_masks(&masks, &[1.0; 20], &ConsensusOptions::default());
        assert_eq!(merged, vec![range(0..20)]);
    }

    #[test]
    fn later_passes_merge_what_the_first_pass_made_overlap() {
        // A and C merge in pass 1 (IoU 1/3); B overlaps each by 2 of 5 faces (IoU 0.15) but
        // the union A + C by 4 of 5 (IoU 0.25), so it joins in pass 2.
        let a = range(0..10);
        let c = range(5..15);
        let b = vec![0, 1, 13, 14, 30];
        let masks = vec![a, b, c];
        let area = [1.0; 31];
        let all = merge_masks(&masks, &area, &ConsensusOptions::default());
        let mut expected = range(0..15);
        expected.push(30);
        assert_eq!(all, vec![expected]);
        let one_pass = ConsensusOptions {
            max_passes: 1,
            ..ConsensusOptions::default()
        };
        // After one pass B's shared faces have one vote in B and one in A + C: the tie goes to
        // the smaller, more specific B.
        let first = merge_masks(&masks, &area, &one_pass);
        assert_eq!(first, vec![range(2..13), vec![0, 1, 13, 14, 30]]);
    }

    #[test]
    fn a_face_in_two_unmerged_masks_goes_to_the_one_more_views_gave_it_to() {
        // Two views agree on 0..4 (two votes for face 3); a third mask 3..13 is larger but gives
        // face 3 only one vote.
        let masks = vec![range(0..4), range(0..4), range(3..13)];
        let merged = merge_masks(&masks, &[1.0; 13], &ConsensusOptions::default());
        assert_eq!(merged, vec![range(4..13), range(0..4)]);
    }

    #[test]
    fn the_two_sides_of_a_thin_part_merge_on_the_faces_both_views_saw() {
        // A slab: top 0..8 (seen from above, view 0), bottom 8..16 (seen from below, view 1),
        // rim 16..20 (seen by both). Each view's mask is one side plus the rim: IoU 4 / 20.
        let top: FaceSet = (0..8).chain(16..20).collect();
        let bottom: FaceSet = (8..20).collect();
        let area = [1.0; 20];
        let options = ConsensusOptions {
            iou_min: 0.25,
            ..ConsensusOptions::default()
        };
        let plain = merge_masks(&[top.clone(), bottom.clone()], &area, &options);
        assert_eq!(plain.len(), 2);
        // On the faces both views saw (the rim) they agree: IoU 1.
        let per_view = vec![vec![top.clone()], vec![bottom.clone()]];
        assert_eq!(
            merge_view_masks(&per_view, &area, &options),
            vec![range(0..20)]
        );
        // A body mask beside the slab in both views, sharing one contaminated face with the
        // top: both views saw the body, so most of it counts, and it stays apart.
        let body: FaceSet = (19..40).collect();
        let area = [1.0; 40];
        let per_view = vec![vec![top, body.clone()], vec![bottom, body]];
        let merged = merge_view_masks(&per_view, &area, &options);
        assert_eq!(merged.len(), 2, "{merged:?}");
    }
}
