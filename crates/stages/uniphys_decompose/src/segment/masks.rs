//! Overlapping binary masks (as a SAM-compatible automatic mask generator returns them) to one
//! label map, after reference §3.1 with thresholds relative to the object's foreground.

use super::{LabelMap, NO_LABEL};

/// One binary mask over a view.
#[derive(Debug, Clone, PartialEq)]
pub struct PixelMask {
    /// Row-major membership, one entry per pixel of the view.
    pub pixels: Vec<bool>,
    /// The producer's quality score (predicted IoU or stability); orders masks of equal area.
    pub score: f32,
}

/// Thresholds of [`label_map_from_masks`], as fractions of the foreground pixel count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskOptions {
    /// The largest mask is taken for the whole object, and dropped, when it covers at least this
    /// fraction of the foreground (default 0.9).
    pub whole_object_fraction: f64,
    /// Regions smaller than this fraction of the foreground become unlabelled (default 0.002;
    /// the reference's fixed 200 px is 0.1 % to 0.3 % of a typical 800 x 800 foreground).
    pub min_region_fraction: f64,
}

impl Default for MaskOptions {
    fn default() -> Self {
        Self {
            whole_object_fraction: 0.9,
            min_region_fraction: 0.002,
        }
    }
}

/// The label map of a view from overlapping masks.
///
/// Only foreground pixels are labelled; they start as "foreground covered by no mask" (one
/// region, lifted like any other, as in the reference). Masks are painted by area, largest
/// first (equal areas: higher score first, then input order), so smaller masks overwrite the
/// larger ones they lie in. Regions below [`MaskOptions::min_region_fraction`] of the
/// foreground become [`NO_LABEL`]; the rest are numbered `0..n` in row-major order of their first
/// pixel. Masks whose length is not `width_px * height_px` are ignored; a short `foreground`
/// counts the missing pixels as background.
#[must_use]
pub fn label_map_from_masks(
    width_px: u32,
    height_px: u32,
    foreground: &[bool],
    masks: &[PixelMask],
    options: &MaskOptions,
) -> LabelMap {
    let pixel_count = width_px as usize * height_px as usize;
    let is_foreground = |i: usize| foreground.get(i).copied().unwrap_or(false);
    let foreground_px = (0..pixel_count).filter(|&i| is_foreground(i)).count();
    let mut map = LabelMap::unlabelled(width_px, height_px);
    if foreground_px == 0 {
        return map;
    }
    for (i, label) in map.labels.iter_mut().enumerate() {
        if is_foreground(i) {
            *label = 0;
        }
    }

    let mut ranked: Vec<(usize, usize)> = masks
        .iter()
        .enumerate()
        .filter(|(_, m)| m.pixels.len() == pixel_count)
        .map(|(index, m)| {
            let area_px = m
                .pixels
                .iter()
                .enumerate()
                .filter(|&(i, &on)| on && is_foreground(i))
                .count();
            (index, area_px)
        })
        .filter(|&(_, area_px)| area_px > 0)
        .collect();
    ranked.sort_by(|&(ia, aa), &(ib, ab)| {
        ab.cmp(&aa)
            .then(masks[ib].score.total_cmp(&masks[ia].score))
            .then(ia.cmp(&ib))
    });

    // The reference always drops the largest mask, assuming it is the whole object. We drop it
    // only when it covers (nearly) the whole foreground: then, as its own region, it would merely
    // duplicate "foreground covered by no mask" (label 0). When it covers less it is a real
    // part (the body of a cabinet, say), and dropping it would fold that part into label 0
    // together with every sliver no mask covers.
    let whole_object_px = options.whole_object_fraction * foreground_px as f64;
    let skip_first = ranked
        .first()
        .is_some_and(|&(_, area_px)| area_px as f64 >= whole_object_px);
    for (rank, &(index, _)) in ranked.iter().enumerate().skip(usize::from(skip_first)) {
        let label = i32::try_from(rank + 1).unwrap_or(i32::MAX);
        for (i, &on) in masks[index].pixels.iter().enumerate() {
            if on && is_foreground(i) {
                map.labels[i] = label;
            }
        }
    }

    drop_small_regions(&mut map, foreground_px, options.min_region_fraction);
    map.canonicalise();
    map
}

/// Unlabels every region with fewer pixels than `min_fraction` of `foreground_px` (at least one
/// pixel is always required).
pub(crate) fn drop_small_regions(map: &mut LabelMap, foreground_px: usize, min_fraction: f64) {
    let min_px = ((min_fraction.max(0.0) * foreground_px as f64).ceil() as usize).max(1);
    let max_label = map.labels.iter().copied().max().unwrap_or(NO_LABEL);
    if max_label < 0 {
        return;
    }
    let mut count = vec![0usize; max_label as usize + 1];
    for &label in &map.labels {
        if label >= 0 {
            count[label as usize] += 1;
        }
    }
    for label in &mut map.labels {
        if *label >= 0 && count[*label as usize] < min_px {
            *label = NO_LABEL;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 x 10 view whose foreground is the rectangle x in 2..18, y in 1..9 (128 px).
    fn foreground() -> Vec<bool> {
        (0..200)
            .map(|i| {
                let (x, y) = (i % 20, i / 20);
                (2..18).contains(&x) && (1..9).contains(&y)
            })
            .collect()
    }

    fn rect_mask(x: std::ops::Range<usize>, y: std::ops::Range<usize>, score: f32) -> PixelMask {
        PixelMask {
            pixels: (0..200)
                .map(|i| x.contains(&(i % 20)) && y.contains(&(i / 20)))
                .collect(),
            score,
        }
    }

    fn label_at(map: &LabelMap, x: u32, y: u32) -> i32 {
        map.get(x, y).unwrap_or(i32::MIN)
    }

    #[test]
    fn smaller_masks_overwrite_larger_ones_and_the_whole_object_mask_is_dropped() {
        let masks = [
            rect_mask(12..16, 3..7, 0.9), // 16 px, inside the body
            rect_mask(0..20, 0..10, 0.9), // the whole object (128 px of foreground)
            rect_mask(2..12, 1..9, 0.9),  // left body, 80 px
        ];
        let map = label_map_from_masks(20, 10, &foreground(), &masks, &MaskOptions::default());
        // Background stays unlabelled, even where the whole-object mask spills over it.
        assert_eq!(label_at(&map, 0, 0), NO_LABEL);
        let left = label_at(&map, 3, 2);
        let small = label_at(&map, 13, 4);
        let rest = label_at(&map, 17, 8);
        assert!(left >= 0 && small >= 0 && rest >= 0);
        assert_ne!(left, small);
        assert_ne!(small, rest);
        // The whole-object mask was dropped: the uncovered right strip is its own region
        // ("covered by no mask"), not merged with anything.
        assert_ne!(rest, left);
        assert_eq!(map.region_count(), 3);
        // Canonical numbering: first pixel in row-major order is region 0.
        assert_eq!(label_at(&map, 2, 1), 0);
    }

    #[test]
    fn a_largest_mask_that_is_not_the_whole_object_is_kept() {
        // 80 of 128 foreground pixels: a real part, kept apart from the uncovered remainder.
        let masks = [rect_mask(2..12, 1..9, 0.5)];
        let map = label_map_from_masks(20, 10, &foreground(), &masks, &MaskOptions::default());
        assert_eq!(map.region_count(), 2);
        assert_ne!(label_at(&map, 3, 2), label_at(&map, 15, 2));
        // With a lower whole-object threshold the same mask counts as the object and is dropped.
        let options = MaskOptions {
            whole_object_fraction: 0.5,
            ..MaskOptions::default()
        };
        let map = label_map_from_masks(20, 10, &foreground(), &masks, &options);
        assert_eq!(map.region_count(), 1);
    }

    #[test]
    fn regions_below_the_relative_minimum_are_unlabelled() {
        // A 4 px mask is 3 % of the foreground: kept at 2 %, dropped at 5 %.
        let masks = [rect_mask(4..6, 4..6, 0.5)];
        let keep = MaskOptions {
            min_region_fraction: 0.02,
            ..MaskOptions::default()
        };
        let map = label_map_from_masks(20, 10, &foreground(), &masks, &keep);
        assert_eq!(map.region_count(), 2);
        let drop = MaskOptions {
            min_region_fraction: 0.05,
            ..MaskOptions::default()
        };
        let map = label_map_from_masks(20, 10, &foreground(), &masks, &drop);
        assert_eq!(map.region_count(), 1);
        assert_eq!(label_at(&map, 4, 4), NO_LABEL);
        assert_eq!(label_at(&map, 7, 4), 0);
    }

    #[test]
    fn equal_areas_are_ordered_by_score_and_bad_lengths_ignored() {
        // Two overlapping 24 px masks: the lower score is painted last and wins the overlap.
        let high = rect_mask(4..10, 2..6, 0.9);
        let low = rect_mask(6..12, 2..6, 0.1);
        let broken = PixelMask {
            pixels: vec![true; 7],
            score: 1.0,
        };
        let options = MaskOptions::default();
        let a = label_map_from_masks(
            20,
            10,
            &foreground(),
            &[high.clone(), low.clone()],
            &options,
        );
        let b = label_map_from_masks(20, 10, &foreground(), &[low, broken, high], &options);
        assert_eq!(a, b);
        // The overlap column x = 7 belongs to the low-score mask, like x = 11.
        assert_eq!(label_at(&a, 7, 3), label_at(&a, 11, 3));
        assert_ne!(label_at(&a, 5, 3), label_at(&a, 7, 3));
    }
}
