//! Choosing the candidate decomposition that best explains the lifted masks (reference §3.5):
//! per view, masks and parts (restricted to the faces the view's masks cover) are matched by the
//! Hungarian method on `1 - IoU` of face areas; the view's loss is
//! `1 - mean(matched IoU) * alpha_v` with `alpha_v` the share of the visible surface the matched
//! masks cover; the candidate's loss is the mean over views; ties go to the smallest K.

use crate::candidates::{Candidate, FaceAdjacency, UnionFind, welded_vertex_ids};
use crate::{DecomposeError, DecomposeResult};
use uniphys_geometry::min_cost_assignment;

/// Losses closer than this are a tie.
const TIE: f64 = 1e-12;

/// The outcome of [`select_candidate`].
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Index of the chosen candidate.
    pub index: usize,
    /// Its part count.
    pub k: usize,
    /// Its loss.
    pub loss: f64,
    /// `(k, loss)` of every candidate, in input order.
    pub losses: Vec<(usize, f64)>,
}

/// The masks of every view without the ones that cover the whole object: a mask holding at least
/// `whole_fraction` of the area the view's masks cover says nothing about parts (the reference
/// drops the largest SAM mask of every view for the same reason).
#[must_use]
pub fn without_whole_object_masks(
    per_view: &[Vec<Vec<u32>>],
    face_area_m2: &[f64],
    whole_fraction: f64,
) -> Vec<Vec<Vec<u32>>> {
    let area = |m: &[u32]| -> f64 {
        m.iter()
            .map(|&f| face_area_m2.get(f as usize).copied().unwrap_or(0.0))
            .sum()
    };
    per_view
        .iter()
        .map(|masks| {
            let total: f64 = masks.iter().map(|m| area(m)).sum();
            masks
                .iter()
                .filter(|m| total <= 0.0 || area(m) < whole_fraction * total)
                .cloned()
                .collect()
        })
        .collect()
}

/// Number of connected components (faces sharing a welded edge) holding at least `min_fraction`
/// of the surface area: the part count the geometry alone suggests (at least 1).
#[must_use]
pub fn substantial_components(mesh: &uniphys_geometry::TriMesh, min_fraction: f64) -> usize {
    let faces = mesh.triangle_count();
    let adjacency = FaceAdjacency::new(mesh, &welded_vertex_ids(mesh));
    let mut uf = UnionFind::new(faces);
    for &(a, b) in &adjacency.pairs {
        uf.union(a, b);
    }
    let mut area = vec![0.0f64; faces];
    for f in 0..faces {
        area[uf.find(u32::try_from(f).unwrap_or(0)) as usize] += mesh.face_area(f);
    }
    let total: f64 = area.iter().sum();
    area.iter()
        .filter(|&&a| a > 0.0 && a >= min_fraction * total)
        .count()
        .max(1)
}

/// The candidate whose K is closest to `k` (the smaller on ties), for when no view has an
/// informative mask; every loss is reported as NaN.
pub fn closest_k(candidates: &[Candidate], k: usize) -> DecomposeResult<Selection> {
    let index = (0..candidates.len())
        .min_by_key(|&i| (candidates[i].k.abs_diff(k), candidates[i].k))
        .ok_or_else(|| {
            DecomposeError::InvalidInput("no candidate decomposition to choose from".into())
        })?;
    Ok(Selection {
        index,
        k: candidates[index].k,
        loss: f64::NAN,
        losses: candidates.iter().map(|c| (c.k, f64::NAN)).collect(),
    })
}

/// Surface area covered by any mask of any view (the "visible" surface of the reference).
#[must_use]
pub fn visible_area_m2(per_view: &[Vec<Vec<u32>>], face_area_m2: &[f64]) -> f64 {
    let mut seen = vec![false; face_area_m2.len()];
    let mut total = 0.0;
    for &f in per_view.iter().flatten().flatten() {
        if let Some(s) = seen.get_mut(f as usize)
            && !*s
        {
            *s = true;
            total += face_area_m2[f as usize];
        }
    }
    total
}

/// The multi-view loss of one face labelling against the per-view masks (face sets); views
/// without masks are left out. `visible_area_m2` is the denominator of `alpha_v`.
pub fn multi_view_loss(
    face_labels: &[u32],
    per_view: &[Vec<Vec<u32>>],
    face_area_m2: &[f64],
    visible_area_m2: f64,
) -> DecomposeResult<f64> {
    if face_labels.len() != face_area_m2.len() {
        return Err(DecomposeError::InvalidInput(format!(
            "{} labels for {} faces",
            face_labels.len(),
            face_area_m2.len()
        )));
    }
    let parts = face_labels.iter().max().map_or(0, |&m| m as usize + 1);
    let mut losses = Vec::new();
    for masks in per_view {
        let masks: Vec<&Vec<u32>> = masks.iter().filter(|m| !m.is_empty()).collect();
        if masks.is_empty() {
            continue;
        }
        // Faces of the view, and part areas restricted to them.
        let mut view_faces: Vec<u32> = masks.iter().flat_map(|m| m.iter().copied()).collect();
        view_faces.sort_unstable();
        view_faces.dedup();
        if let Some(&f) = view_faces.last()
            && f as usize >= face_labels.len()
        {
            return Err(DecomposeError::InvalidInput(format!(
                "a mask names face {f} of {}",
                face_labels.len()
            )));
        }
        let mut part_area = vec![0.0f64; parts];
        let mut seen = vec![false; parts];
        for &f in &view_faces {
            let p = face_labels[f as usize] as usize;
            part_area[p] += face_area_m2[f as usize];
            seen[p] = true;
        }
        // Dense column index of the parts present in the view.
        let mut column = vec![usize::MAX; parts];
        let mut present = Vec::new();
        for p in (0..parts).filter(|&p| seen[p]) {
            column[p] = present.len();
            present.push(p);
        }
        let cols = present.len();
        let mut inter = vec![0.0f64; masks.len() * cols];
        let mut mask_area = vec![0.0f64; masks.len()];
        for (i, mask) in masks.iter().enumerate() {
            for &f in mask.iter() {
                let a = face_area_m2[f as usize];
                mask_area[i] += a;
                inter[i * cols + column[face_labels[f as usize] as usize]] += a;
            }
        }
        let iou = |i: usize, j: usize| -> f64 {
            let x = inter[i * cols + j];
            let union = mask_area[i] + part_area[present[j]] - x;
            if union > 0.0 { x / union } else { 0.0 }
        };
        let cost: Vec<f64> = (0..masks.len())
            .flat_map(|i| (0..cols).map(move |j| (i, j)))
            .map(|(i, j)| 1.0 - iou(i, j))
            .collect();
        let assignment = min_cost_assignment(&cost, masks.len(), cols)?;
        let mut matched_iou = Vec::new();
        let mut covered = vec![false; face_labels.len()];
        let mut covered_area = 0.0;
        for (i, j) in assignment.iter().enumerate() {
            if let Some(j) = j {
                matched_iou.push(iou(i, *j));
                for &f in masks[i].iter() {
                    if !covered[f as usize] {
                        covered[f as usize] = true;
                        covered_area += face_area_m2[f as usize];
                    }
                }
            }
        }
        let mean = matched_iou.iter().sum::<f64>() / matched_iou.len().max(1) as f64;
        let alpha = if visible_area_m2 > 0.0 {
            covered_area / visible_area_m2
        } else {
            0.0
        };
        losses.push(1.0 - mean * alpha);
    }
    if losses.is_empty() {
        return Err(DecomposeError::InvalidInput(
            "no view has a mask to match candidates against".into(),
        ));
    }
    Ok(losses.iter().sum::<f64>() / losses.len() as f64)
}

/// The candidate with the smallest [`multi_view_loss`]; among equal losses the smallest K.
pub fn select_candidate(
    candidates: &[Candidate],
    per_view: &[Vec<Vec<u32>>],
    face_area_m2: &[f64],
) -> DecomposeResult<Selection> {
    let visible = visible_area_m2(per_view, face_area_m2);
    let mut losses = Vec::with_capacity(candidates.len());
    let mut best: Option<(usize, f64)> = None;
    for (index, candidate) in candidates.iter().enumerate() {
        let loss = multi_view_loss(&candidate.face_labels, per_view, face_area_m2, visible)?;
        losses.push((candidate.k, loss));
        let better = match best {
            None => true,
            Some((b, bl)) => loss < bl - TIE || (loss <= bl + TIE && candidate.k < candidates[b].k),
        };
        if better {
            best = Some((index, loss));
        }
    }
    let (index, loss) = best.ok_or_else(|| {
        DecomposeError::InvalidInput("no candidate decomposition to choose from".into())
    })?;
    Ok(Selection {
        index,
        k: candidates[index].k,
        loss,
        losses,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eight unit-area faces; the true parts are {0..4} and {4..8}.
    fn views() -> Vec<Vec<Vec<u32>>> {
        vec![
            vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7]],
            vec![vec![0, 1, 2], vec![4, 5]],
            vec![],
        ]
    }

    fn candidate(k: usize, labels: &[u32]) -> Candidate {
        Candidate {
            k,
            face_labels: labels.to_vec(),
        }
    }

    #[test]
    fn the_labelling_that_matches_the_masks_wins() {
        let areas = vec![1.0; 8];
        let candidates = vec![
            candidate(1, &[0; 8]),
            candidate(2, &[0, 0, 0, 0, 1, 1, 1, 1]),
            candidate(3, &[0, 0, 1, 1, 2, 2, 2, 2]),
            candidate(2, &[0, 0, 1, 1, 1, 1, 1, 1]),
        ];
        let selection = select_candidate(&candidates, &views(), &areas).unwrap();
        assert_eq!(selection.index, 1);
        assert_eq!(selection.k, 2);
        // View 0: both IoUs 1, alpha 1 -> 0. View 1: faces {0,1,2,4,5}; IoUs 1 and 1, alpha 5/8.
        let expected = (0.0 + (1.0 - 5.0 / 8.0)) / 2.0;
        assert!((selection.loss - expected).abs() < 1e-12);
        // K = 1: view 0 one match IoU 0.5, alpha 0.5 -> 0.75; view 1: IoU 3/5, alpha 3/8.
        let k1 = (0.75 + (1.0 - 0.6 * 3.0 / 8.0)) / 2.0;
        assert!((selection.losses[0].1 - k1).abs() < 1e-12);
    }

    #[test]
    fn whole_object_masks_are_dropped_and_the_geometry_decides_without_masks() {
        let areas = vec![1.0; 8];
        let views = vec![
            vec![(0..8).collect::<Vec<u32>>()],
            vec![vec![0, 1, 2, 3, 4, 5, 6], vec![7]],
        ];
        let informative = without_whole_object_masks(&views, &areas, 0.85);
        assert_eq!(informative, vec![vec![], vec![vec![7]]]);
        let candidates = vec![
            candidate(1, &[0; 8]),
            candidate(3, &[0, 0, 0, 1, 1, 1, 2, 2]),
        ];
        assert_eq!(closest_k(&candidates, 2).unwrap().k, 1);
        assert_eq!(closest_k(&candidates, 5).unwrap().index, 1);
        // Two far boxes and a speck: two substantial components.
        use uniphys_geometry::{DVec3, TriMesh};
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::splat(2.0), DVec3::splat(3.0));
        let c = TriMesh::cuboid(DVec3::splat(5.0), DVec3::splat(5.01));
        assert_eq!(
            substantial_components(&TriMesh::merge([&a, &b, &c]), 0.01),
            2
        );
    }

    #[test]
    fn ties_go_to_the_smallest_k_and_empty_inputs_are_refused() {
        let areas = vec![1.0; 8];
        // Same labelling offered as K = 3 first and K = 2 later.
        let labels = [0, 0, 0, 0, 1, 1, 1, 1];
        let candidates = vec![candidate(3, &labels), candidate(2, &labels)];
        let selection = select_candidate(&candidates, &views(), &areas).unwrap();
        assert_eq!(selection.k, 2);
        assert!(select_candidate(&[], &views(), &areas).is_err());
        assert!(select_candidate(&candidates, &[vec![]], &areas).is_err());
    }
}
