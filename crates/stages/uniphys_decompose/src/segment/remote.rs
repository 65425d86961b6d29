//! A [`Segmenter`] backed by a SAM-compatible mask service ([`uniphys_vision::SamClient`]):
//! each view's colour image goes out as a PNG, the overlapping masks that come back become a
//! label map through [`label_map_from_masks`] over the view's rendered foreground.

use std::collections::BTreeSet;
use std::sync::Mutex;

use uniphys_vision::SamClient;

use crate::segment::{
    LabelMap, MaskOptions, PixelMask, Segmenter, ViewImage, label_map_from_masks,
};
use crate::{DecomposeError, DecomposeResult};

/// Segments views with a SAM-compatible service; the provider names the model that answered.
#[derive(Debug)]
pub struct SamSegmenter {
    client: SamClient,
    generation: uniphys_vision::MaskOptions,
    masks: MaskOptions,
    models: Mutex<BTreeSet<String>>,
}

impl SamSegmenter {
    /// A segmenter asking `client` with the reference's generation settings and the default
    /// mask-to-label thresholds.
    #[must_use]
    pub fn new(client: SamClient) -> Self {
        Self::with_options(
            client,
            uniphys_vision::MaskOptions::default(),
            MaskOptions::default(),
        )
    }

    /// A segmenter with explicit generation settings (sent to the service) and label-map
    /// thresholds (applied here).
    #[must_use]
    pub fn with_options(
        client: SamClient,
        generation: uniphys_vision::MaskOptions,
        masks: MaskOptions,
    ) -> Self {
        Self {
            client,
            generation,
            masks,
            models: Mutex::new(BTreeSet::new()),
        }
    }
}

impl Segmenter for SamSegmenter {
    /// `"sam:<model>"` with the model the service named (models joined by `+` if views were
    /// answered by different ones; `"sam:unknown"` before the first answer).
    fn provider(&self) -> String {
        let models = self
            .models
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if models.is_empty() {
            return "sam:unknown".to_owned();
        }
        let names: Vec<&str> = models.iter().map(String::as_str).collect();
        format!("sam:{}", names.join("+"))
    }

    fn segment(&self, view: &ViewImage<'_>) -> DecomposeResult<LabelMap> {
        let (width_px, height_px) = (view.colour.width_px, view.colour.height_px);
        if (view.face_ids.width_px, view.face_ids.height_px) != (width_px, height_px) {
            return Err(DecomposeError::Segmentation {
                view: view.index,
                message: format!(
                    "face-ID image is {}x{} px but the colour image {width_px}x{height_px} px",
                    view.face_ids.width_px, view.face_ids.height_px
                ),
            });
        }
        let png = uniphys_render::encode_png(view.colour).map_err(|error| {
            DecomposeError::Segmentation {
                view: view.index,
                message: format!("cannot encode the view as PNG: {error}"),
            }
        })?;
        let answer = self
            .client
            .masks(&png, width_px, height_px, &self.generation)?;
        self.models
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .insert(answer.model);
        let foreground: Vec<bool> = view.face_ids.face.iter().map(|&face| face != 0).collect();
        let masks: Vec<PixelMask> = answer
            .masks
            .into_iter()
            .map(|mask| PixelMask {
                pixels: mask.pixels,
                score: mask.predicted_iou,
            })
            .collect();
        Ok(label_map_from_masks(
            width_px,
            height_px,
            &foreground,
            &masks,
            &self.masks,
        ))
    }
}
