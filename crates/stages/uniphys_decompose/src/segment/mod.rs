//! 2D segmentation of the rendered views: the [`Segmenter`] interface, the label map it returns,
//! the built-in render-space segmenter ([`BuiltinSegmenter`]) and the conversion of overlapping
//! masks (as a SAM-compatible service returns them) to a label map ([`label_map_from_masks`]).

pub mod builtin;
pub mod masks;
pub mod remote;
#[cfg(test)]
pub(crate) mod test_meshes;

use uniphys_render::{Camera, FaceIdImage, RgbaImage};

use crate::DecomposeResult;

pub use builtin::{BUILTIN_PROVIDER, BuiltinOptions, BuiltinSegmenter};
pub use masks::{MaskOptions, PixelMask, label_map_from_masks};
pub use remote::SamSegmenter;

/// Label of pixels that belong to no region (background or ignored).
pub const NO_LABEL: i32 = -1;

/// One region label per pixel of a view.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LabelMap {
    /// Image width in pixels.
    pub width_px: u32,
    /// Image height in pixels.
    pub height_px: u32,
    /// Row-major labels: [`NO_LABEL`] (-1) for background or ignored pixels, `>= 0` a region.
    pub labels: Vec<i32>,
}

impl LabelMap {
    /// A map of the given size with every pixel unlabelled.
    #[must_use]
    pub fn unlabelled(width_px: u32, height_px: u32) -> Self {
        Self {
            width_px,
            height_px,
            labels: vec![NO_LABEL; width_px as usize * height_px as usize],
        }
    }

    /// The label at a pixel, `None` outside the image.
    #[must_use]
    pub fn get(&self, x_px: u32, y_px: u32) -> Option<i32> {
        if x_px >= self.width_px || y_px >= self.height_px {
            return None;
        }
        self.labels
            .get(y_px as usize * self.width_px as usize + x_px as usize)
            .copied()
    }

    /// Number of distinct region labels (`>= 0`).
    #[must_use]
    pub fn region_count(&self) -> usize {
        let mut seen: Vec<i32> = self.labels.iter().copied().filter(|&l| l >= 0).collect();
        seen.sort_unstable();
        seen.dedup();
        seen.len()
    }

    /// Renumbers the regions `0..n` in the order of their first pixel (row-major), so equal
    /// partitions give equal maps whatever the producer's label values were.
    pub fn canonicalise(&mut self) {
        let max_label = self.labels.iter().copied().max().unwrap_or(NO_LABEL);
        if max_label < 0 {
            self.labels.fill(NO_LABEL);
            return;
        }
        let mut next = 0i32;
        if max_label < DENSE_RENUMBER_LIMIT {
            let mut map = vec![NO_LABEL; max_label as usize + 1];
            for label in &mut self.labels {
                if *label < 0 {
                    *label = NO_LABEL;
                    continue;
                }
                let slot = &mut map[*label as usize];
                if *slot < 0 {
                    *slot = next;
                    next += 1;
                }
                *label = *slot;
            }
        } else {
            let mut map = std::collections::BTreeMap::new();
            for label in &mut self.labels {
                if *label < 0 {
                    *label = NO_LABEL;
                    continue;
                }
                *label = *map.entry(*label).or_insert_with(|| {
                    next += 1;
                    next - 1
                });
            }
        }
    }
}

/// Labels below this are renumbered through a lookup table, larger ones through a sorted map.
const DENSE_RENUMBER_LIMIT: i32 = 1 << 20;

/// Everything a segmenter may look at for one view.
#[derive(Debug, Clone, Copy)]
pub struct ViewImage<'a> {
    /// Index of the view in the view set.
    pub index: usize,
    /// The camera of the view.
    pub camera: &'a Camera,
    /// Visible face, depth and normal per pixel.
    pub face_ids: &'a FaceIdImage,
    /// Shaded colour image (transparent background).
    pub colour: &'a RgbaImage,
    /// Material index of every face of the mesh (empty: materials unknown).
    pub face_material: &'a [u32],
}

/// A source of per-view 2D segmentations.
pub trait Segmenter: Send + Sync {
    /// Who produced the masks, e.g. "builtin-render-segmenter" or `sam:<model>`.
    fn provider(&self) -> String;
    /// The label map of one view, the same size as the view's images.
    fn segment(&self, view: &ViewImage<'_>) -> DecomposeResult<LabelMap>;
}
