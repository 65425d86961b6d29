//! Client of a PartField-compatible per-face feature service (`POST /v1/part-features`).

use crate::contract::{HEALTH_PATH, PART_FEATURES_PATH, PartFeatureRequest, PartFeatureResponse};
use crate::transport::Transport;
use crate::{ClientConfig, VisionError, VisionResult};

const SERVICE: &str = "partfield";

/// Per-face feature vectors of a mesh, checked against it.
#[derive(Debug, Clone, PartialEq)]
pub struct PartFeatures {
    /// The checkpoint that answered.
    pub model: String,
    /// Dimensions per face.
    pub dims: usize,
    /// `face_count x dims`, face by face in the order of the request's faces; all finite.
    pub features: Vec<f32>,
}

impl PartFeatures {
    /// Number of faces.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.features.len().checked_div(self.dims).unwrap_or(0)
    }

    /// The feature vector of face `face`, `None` past the last face.
    #[must_use]
    pub fn row(&self, face: usize) -> Option<&[f32]> {
        let start = face.checked_mul(self.dims)?;
        self.features.get(start..start.checked_add(self.dims)?)
    }
}

/// Blocking client of a PartField-compatible feature service (`proto/vision.openapi.yaml`).
#[derive(Debug)]
pub struct PartFieldClient {
    transport: Transport,
}

impl PartFieldClient {
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

    /// Per-face features of the triangle mesh (`vertices_m` in metres, object frame).
    ///
    /// # Errors
    /// [`VisionError::InvalidInput`] for an empty mesh, a non-finite vertex or an index out of
    /// range; the transport errors; [`VisionError::InvalidAnswer`] if the feature count is not
    /// faces x dims or a value is not finite.
    pub fn features(
        &self,
        vertices_m: &[[f32; 3]],
        faces: &[[u32; 3]],
    ) -> VisionResult<PartFeatures> {
        let request = encode_mesh(vertices_m, faces)?;
        let response: PartFeatureResponse = self.transport.post(PART_FEATURES_PATH, &request)?;
        decode_features(response, faces.len())
    }
}

fn encode_mesh(vertices_m: &[[f32; 3]], faces: &[[u32; 3]]) -> VisionResult<PartFeatureRequest> {
    let invalid = |reason: String| VisionError::InvalidInput {
        service: SERVICE,
        reason,
    };
    if faces.is_empty() {
        return Err(invalid("the mesh has no faces".to_owned()));
    }
    let too_many = |what: &str| invalid(format!("the mesh has more than u32::MAX {what}"));
    let vertex_count = u32::try_from(vertices_m.len()).map_err(|_| too_many("vertices"))?;
    let face_count = u32::try_from(faces.len()).map_err(|_| too_many("faces"))?;
    if let Some(index) = vertices_m
        .iter()
        .position(|v| v.iter().any(|c| !c.is_finite()))
    {
        return Err(invalid(format!(
            "vertex {index} is not finite: {:?}",
            vertices_m[index]
        )));
    }
    if let Some(index) = faces
        .iter()
        .position(|f| f.iter().any(|&i| i >= vertex_count))
    {
        return Err(invalid(format!(
            "face {index} {:?} refers to a vertex past the last ({vertex_count} vertices)",
            faces[index]
        )));
    }
    let vertex_bytes: Vec<u8> = vertices_m
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let face_bytes: Vec<u8> = faces
        .iter()
        .flatten()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    Ok(PartFeatureRequest {
        vertex_count,
        face_count,
        vertices_f32_base64: base64::encode(vertex_bytes),
        faces_u32_base64: base64::encode(face_bytes),
    })
}

fn decode_features(response: PartFeatureResponse, face_count: usize) -> VisionResult<PartFeatures> {
    let invalid = |reason: String| VisionError::InvalidAnswer {
        service: SERVICE,
        path: PART_FEATURES_PATH,
        reason,
    };
    if response.model.trim().is_empty() {
        return Err(invalid("the answer names no model".to_owned()));
    }
    let dims = response.dims as usize;
    if dims == 0 {
        return Err(invalid("dims is 0".to_owned()));
    }
    let bytes = base64::decode(response.features_f32_base64.trim())
        .map_err(|error| invalid(format!("features_f32_base64 is not base64 ({error})")))?;
    if bytes.len() % 4 != 0 {
        return Err(invalid(format!(
            "features_f32_base64 holds {} bytes, not a whole number of f32",
            bytes.len()
        )));
    }
    let values = bytes.len() / 4;
    if Some(values) != face_count.checked_mul(dims) {
        return Err(invalid(format!(
            "{values} feature values but faces x dims = {face_count} x {dims}"
        )));
    }
    let features: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    if let Some(index) = features.iter().position(|v| !v.is_finite()) {
        return Err(invalid(format!(
            "feature of face {} dimension {} is {}",
            index / dims,
            index % dims,
            features[index]
        )));
    }
    Ok(PartFeatures {
        model: response.model,
        dims,
        features,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_is_encoded_little_endian_and_checked() {
        let request = encode_mesh(&[[1.0, 0.0, -2.5], [0.0; 3], [0.0; 3]], &[[0, 1, 2]]).unwrap();
        let vertices = base64::decode(&request.vertices_f32_base64).unwrap();
        assert_eq!(vertices.len(), 36);
        assert_eq!(vertices[..4], 1.0f32.to_le_bytes());
        assert_eq!(vertices[8..12], (-2.5f32).to_le_bytes());
        let faces = base64::decode(&request.faces_u32_base64).unwrap();
        assert_eq!(faces[4..8], 1u32.to_le_bytes());
        assert_eq!((request.vertex_count, request.face_count), (3, 1));
        assert!(encode_mesh(&[[0.0; 3]; 3], &[[0, 1, 3]]).is_err());
        assert!(encode_mesh(&[[f32::NAN, 0.0, 0.0], [0.0; 3], [0.0; 3]], &[[0, 1, 2]]).is_err());
        assert!(encode_mesh(&[[0.0; 3]; 3], &[]).is_err());
    }

    #[test]
    fn features_are_decoded_row_by_row() {
        let values: Vec<f32> = (0..6).map(|i| i as f32 * 0.5).collect();
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let response = PartFeatureResponse {
            model: "m".to_owned(),
            dims: 3,
            features_f32_base64: base64::encode(&bytes),
        };
        let features = decode_features(response.clone(), 2).unwrap();
        assert_eq!(features.face_count(), 2);
        assert_eq!(features.row(1), Some([1.5, 2.0, 2.5].as_slice()));
        assert_eq!(features.row(2), None);
        let wrong = decode_features(response, 3).unwrap_err().to_string();
        assert!(wrong.contains("3 x 3"), "{wrong}");
    }
}
