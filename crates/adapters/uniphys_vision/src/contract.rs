//! Wire types of `proto/vision.openapi.yaml`: the SAM-compatible mask service and the
//! PartField-compatible feature service.

use serde::{Deserialize, Serialize};

use crate::Rle;

/// Path of SAM automatic mask generation.
pub const MASKS_PATH: &str = "/v1/masks";
/// Path of PartField per-face features.
pub const PART_FEATURES_PATH: &str = "/v1/part-features";
/// Path of the health check of both services.
pub const HEALTH_PATH: &str = "/healthz";

/// Settings of SAM automatic mask generation (defaults: reference section 3.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MaskOptions {
    /// Point prompts per image side.
    pub points_per_side: u32,
    /// Minimum predicted IoU of a kept mask.
    pub pred_iou_thresh: f32,
    /// Minimum stability score of a kept mask.
    pub stability_score_thresh: f32,
    /// IoU above which box non-maximum suppression drops the weaker mask.
    pub box_nms_thresh: f32,
}

impl Default for MaskOptions {
    fn default() -> Self {
        Self {
            points_per_side: 32,
            pred_iou_thresh: 0.7,
            stability_score_thresh: 0.85,
            box_nms_thresh: 0.7,
        }
    }
}

/// `POST /v1/masks` request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaskRequest {
    /// The RGB(A) image as a base64 (standard alphabet, padded) PNG.
    pub image_png_base64: String,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Generation settings, flattened into the request object.
    #[serde(flatten)]
    pub options: MaskOptions,
}

/// One mask of a `POST /v1/masks` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WireMask {
    /// The mask, uncompressed COCO RLE (column-major).
    pub rle: Rle,
    /// Foreground pixels.
    pub area: u64,
    /// The model's IoU estimate.
    pub predicted_iou: f64,
    /// Stability of the mask under threshold changes.
    pub stability_score: f64,
}

/// `POST /v1/masks` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaskResponse {
    /// The checkpoint that answered, e.g. `sam2_hiera_large`.
    pub model: String,
    /// The masks, in any order; they may overlap.
    pub masks: Vec<WireMask>,
}

/// `POST /v1/part-features` request. Arrays are base64 (standard alphabet, padded) of
/// little-endian values, row by row: a JSON number array would be ~3x larger.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartFeatureRequest {
    /// Number of vertices.
    pub vertex_count: u32,
    /// Number of triangles.
    pub face_count: u32,
    /// `vertex_count x 3` f32 positions (x, y, z), metres, object frame.
    pub vertices_f32_base64: String,
    /// `face_count x 3` u32 vertex indices, 0-based.
    pub faces_u32_base64: String,
}

/// `POST /v1/part-features` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartFeatureResponse {
    /// The checkpoint that answered.
    pub model: String,
    /// Feature dimensions per face.
    pub dims: u32,
    /// `face_count x dims` little-endian f32, face by face in request order.
    pub features_f32_base64: String,
}
