//! Client of a SAM-compatible automatic mask service (`POST /v1/masks`).

use crate::contract::{HEALTH_PATH, MASKS_PATH, MaskOptions, MaskRequest, MaskResponse};
use crate::transport::Transport;
use crate::{ClientConfig, VisionError, VisionResult};

const SERVICE: &str = "sam";

/// One decoded mask of a [`MaskSet`].
#[derive(Debug, Clone, PartialEq)]
pub struct SamMask {
    /// Row-major, `width_px * height_px`; true = in the mask.
    pub pixels: Vec<bool>,
    /// Pixels in the mask.
    pub area_px: u64,
    /// The model's IoU estimate.
    pub predicted_iou: f32,
    /// The mask's stability score.
    pub stability_score: f32,
}

/// The masks of one image, checked against it.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskSet {
    /// The checkpoint that answered.
    pub model: String,
    /// Image width, pixels.
    pub width_px: u32,
    /// Image height, pixels.
    pub height_px: u32,
    /// The masks in the service's order (they may overlap).
    pub masks: Vec<SamMask>,
}

/// Blocking client of a SAM-compatible mask service (`proto/vision.openapi.yaml`).
#[derive(Debug)]
pub struct SamClient {
    transport: Transport,
}

impl SamClient {
    /// A client with `config`.
    ///
    /// # Errors
    /// [`VisionError::InvalidOption`] for bad settings.
    pub fn new(config: ClientConfig) -> VisionResult<Self> {
        Ok(Self {
            transport: Transport::new(config, SERVICE)?,
        })
    }

    /// The settings.
    #[must_use]
    pub fn config(&self) -> &ClientConfig {
        self.transport.config()
    }

    /// One `GET /healthz`, no retries.
    ///
    /// # Errors
    /// [`VisionError::Unhealthy`] or [`VisionError::Refused`].
    pub fn health(&self) -> VisionResult<()> {
        self.transport.health(HEALTH_PATH)
    }

    /// Automatic masks of a PNG image of `width_px x height_px`.
    ///
    /// # Errors
    /// [`VisionError::InvalidInput`] if `png` is not a PNG of that size; the transport errors
    /// ([`VisionError::GaveUp`], [`VisionError::Refused`]); [`VisionError::InvalidAnswer`] if a
    /// mask is not of the image's size, its runs do not cover the image, its area is wrong or
    /// a score is not finite.
    pub fn masks(
        &self,
        png: &[u8],
        width_px: u32,
        height_px: u32,
        options: &MaskOptions,
    ) -> VisionResult<MaskSet> {
        check_png(png, width_px, height_px)?;
        let request = MaskRequest {
            image_png_base64: base64::encode(png),
            width: width_px,
            height: height_px,
            options: *options,
        };
        let response: MaskResponse = self.transport.post(MASKS_PATH, &request)?;
        decode_masks(response, width_px, height_px)
    }
}

/// Checks the PNG signature and that the IHDR chunk states `width_px x height_px`.
fn check_png(png: &[u8], width_px: u32, height_px: u32) -> VisionResult<()> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let invalid = |reason: String| VisionError::InvalidInput {
        service: SERVICE,
        reason,
    };
    if width_px == 0 || height_px == 0 {
        return Err(invalid(format!(
            "the image is {width_px}x{height_px} pixels"
        )));
    }
    let header = png.get(..24).filter(|head| {
        head.starts_with(&SIGNATURE) && head.get(12..16) == Some(b"IHDR".as_slice())
    });
    let Some(header) = header else {
        return Err(invalid("the image bytes are not a PNG".to_owned()));
    };
    let be = |range: std::ops::Range<usize>| {
        header
            .get(range)
            .and_then(|bytes| <[u8; 4]>::try_from(bytes).ok())
            .map_or(0, u32::from_be_bytes)
    };
    let (png_width, png_height) = (be(16..20), be(20..24));
    if (png_width, png_height) != (width_px, height_px) {
        return Err(invalid(format!(
            "the PNG is {png_width}x{png_height} pixels but {width_px}x{height_px} was stated"
        )));
    }
    Ok(())
}

fn decode_masks(response: MaskResponse, width_px: u32, height_px: u32) -> VisionResult<MaskSet> {
    let invalid = |reason: String| VisionError::InvalidAnswer {
        service: SERVICE,
        path: MASKS_PATH,
        reason,
    };
    if response.model.trim().is_empty() {
        return Err(invalid("the answer names no model".to_owned()));
    }
    let mut masks = Vec::with_capacity(response.masks.len());
    for (index, mask) in response.masks.into_iter().enumerate() {
        let pixels = mask
            .rle
            .decode(width_px, height_px)
            .map_err(|reason| invalid(format!("mask {index}: {reason}")))?;
        let area_px = pixels.iter().filter(|&&inside| inside).count() as u64;
        if area_px != mask.area {
            return Err(invalid(format!(
                "mask {index}: area {} but its RLE has {area_px} foreground pixels",
                mask.area
            )));
        }
        for (name, value) in [
            ("predicted_iou", mask.predicted_iou),
            ("stability_score", mask.stability_score),
        ] {
            if !value.is_finite() {
                return Err(invalid(format!("mask {index}: {name} is {value}")));
            }
        }
        masks.push(SamMask {
            pixels,
            area_px,
            predicted_iou: mask.predicted_iou as f32,
            stability_score: mask.stability_score as f32,
        });
    }
    Ok(MaskSet {
        model: response.model,
        width_px,
        height_px,
        masks,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png_header(width_px: u32, height_px: u32) -> Vec<u8> {
        let mut bytes = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13];
        bytes.extend_from_slice(b"IHDR");
        bytes.extend_from_slice(&width_px.to_be_bytes());
        bytes.extend_from_slice(&height_px.to_be_bytes());
        bytes
    }

    #[test]
    fn png_size_is_checked_against_the_stated_size() {
        assert!(check_png(&png_header(32, 16), 32, 16).is_ok());
        let swapped = check_png(&png_header(32, 16), 16, 32)
            .unwrap_err()
            .to_string();
        assert!(swapped.contains("32x16"), "{swapped}");
        assert!(check_png(b"GIF89a not a png at all!!", 32, 16).is_err());
        assert!(check_png(&png_header(0, 0), 0, 0).is_err());
    }
}
