//! Scoring a decomposition against known parts: part-count error and face-area-weighted IoU
//! after Hungarian matching of found parts to true parts.

use crate::{DecomposeError, DecomposeResult};
use uniphys_geometry::min_cost_assignment;

/// How well a decomposition matches the known parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartScore {
    /// Number of true parts.
    pub true_parts: usize,
    /// Number of parts found.
    pub found_parts: usize,
    /// `|found - true|`.
    pub count_error: usize,
    /// Sum over true parts of `area * IoU(matched found part)` over the total area; unmatched true
    /// parts count 0. In [0, 1], 1 for a perfect decomposition.
    pub area_iou: f64,
}

/// Scores `found` (part per face) against `truth` (part per face) with face areas.
pub fn score_parts(
    found: &[u32],
    truth: &[u32],
    face_area_m2: &[f64],
) -> DecomposeResult<PartScore> {
    let matched = match_parts(found, truth, face_area_m2)?;
    let t = matched.iou.len();
    Ok(PartScore {
        true_parts: t,
        found_parts: matched.found_parts,
        count_error: t.abs_diff(matched.found_parts),
        area_iou: matched.area_iou(),
    })
}

/// The one-to-one matching of found parts to true parts that [`score_parts`] scores.
#[derive(Debug, Clone, PartialEq)]
pub struct PartMatching {
    /// Number of found parts.
    pub found_parts: usize,
    /// Per true part, the found part matched to it (none when there are fewer found parts).
    pub found_of_true: Vec<Option<usize>>,
    /// Per true part, its IoU with the matched found part (0 when unmatched).
    pub iou: Vec<f64>,
    /// Per true part, its area.
    pub true_area_m2: Vec<f64>,
}

impl PartMatching {
    /// Sum over true parts of `area * IoU` over their total area: [`PartScore::area_iou`].
    #[must_use]
    pub fn area_iou(&self) -> f64 {
        let total: f64 = self.true_area_m2.iter().sum();
        let weighted: f64 = self
            .true_area_m2
            .iter()
            .zip(&self.iou)
            .map(|(a, iou)| a * iou)
            .sum();
        if total > 0.0 { weighted / total } else { 0.0 }
    }
}

/// Matches found parts to true parts one-to-one (Hungarian, maximising the summed IoU by face
/// area).
pub fn match_parts(
    found: &[u32],
    truth: &[u32],
    face_area_m2: &[f64],
) -> DecomposeResult<PartMatching> {
    if found.len() != truth.len() || found.len() != face_area_m2.len() {
        return Err(DecomposeError::InvalidInput(format!(
            "{} found labels, {} true labels, {} face areas",
            found.len(),
            truth.len(),
            face_area_m2.len()
        )));
    }
    let count = |labels: &[u32]| labels.iter().max().map_or(0, |&m| m as usize + 1);
    let (t, k) = (count(truth), count(found));
    let mut inter = vec![0.0f64; t * k];
    let mut true_area = vec![0.0f64; t];
    let mut found_area = vec![0.0f64; k];
    for f in 0..found.len() {
        let (a, i, j) = (face_area_m2[f], truth[f] as usize, found[f] as usize);
        inter[i * k + j] += a;
        true_area[i] += a;
        found_area[j] += a;
    }
    let iou = |i: usize, j: usize| {
        let x = inter[i * k + j];
        let union = true_area[i] + found_area[j] - x;
        if union > 0.0 { x / union } else { 0.0 }
    };
    let cost: Vec<f64> = (0..t * k).map(|c| 1.0 - iou(c / k, c % k)).collect();
    let assignment = min_cost_assignment(&cost, t, k)?;
    Ok(PartMatching {
        found_parts: k,
        iou: assignment
            .iter()
            .enumerate()
            .map(|(i, j)| j.map_or(0.0, |j| iou(i, j)))
            .collect(),
        found_of_true: assignment,
        true_area_m2: true_area,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perfect_relabelled_split_and_merged_decompositions() {
        let areas = [1.0, 1.0, 2.0, 4.0];
        let truth = [0, 0, 1, 1];
        let perfect = score_parts(&[1, 1, 0, 0], &truth, &areas).unwrap();
        assert_eq!((perfect.count_error, perfect.area_iou), (0, 1.0));
        // Everything in one part: true part 1 (area 6 of 8) matches with IoU 6/8.
        let one = score_parts(&[0; 4], &truth, &areas).unwrap();
        assert_eq!(one.found_parts, 1);
        assert!((one.area_iou - 6.0 * 0.75 / 8.0).abs() < 1e-12);
        // True part 1 split in two: best match IoU 4/6.
        let split = score_parts(&[0, 0, 1, 2], &truth, &areas).unwrap();
        assert_eq!(split.count_error, 1);
        assert!((split.area_iou - (2.0 + 6.0 * 4.0 / 6.0) / 8.0).abs() < 1e-12);
        assert!(score_parts(&[0], &truth, &areas).is_err());
    }
}
