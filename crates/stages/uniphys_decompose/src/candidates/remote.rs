//! A [`CandidateGenerator`] backed by a PartField-compatible feature service
//! ([`uniphys_vision::PartFieldClient`]): per-face features, L2-normalised per face as the
//! reference does, then the shared Ward clustering [`cluster_faces`].

use std::collections::BTreeSet;
use std::sync::Mutex;

use uniphys_vision::PartFieldClient;

use crate::DecomposeResult;
use crate::candidates::{Candidate, CandidateGenerator, CandidateRequest, cluster_faces};

/// Candidates from PartField features; the provider names the model that answered.
#[derive(Debug)]
pub struct PartFieldGenerator {
    client: PartFieldClient,
    models: Mutex<BTreeSet<String>>,
}

impl PartFieldGenerator {
    /// A generator asking `client`.
    #[must_use]
    pub fn new(client: PartFieldClient) -> Self {
        Self {
            client,
            models: Mutex::new(BTreeSet::new()),
        }
    }
}

impl CandidateGenerator for PartFieldGenerator {
    fn learned(&self) -> bool {
        true
    }

    /// `"partfield:<model>"` with the model the service named (`"partfield:unknown"` before
    /// the first answer).
    fn provider(&self) -> String {
        let models = self
            .models
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if models.is_empty() {
            return "partfield:unknown".to_owned();
        }
        let names: Vec<&str> = models.iter().map(String::as_str).collect();
        format!("partfield:{}", names.join("+"))
    }

    fn candidates(&self, request: &CandidateRequest<'_>) -> DecomposeResult<Vec<Candidate>> {
        let vertices_m: Vec<[f32; 3]> = request
            .mesh
            .positions
            .iter()
            .map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect();
        let answer = self.client.features(&vertices_m, &request.mesh.triangles)?;
        self.models
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .insert(answer.model.clone());
        let features = normalised_rows(answer.features, answer.dims);
        cluster_faces(
            request.mesh,
            &features,
            answer.dims,
            request.k_values.clone(),
        )
    }
}

/// Each row of `dims` values scaled to unit length (all-zero rows stay zero).
fn normalised_rows(mut features: Vec<f32>, dims: usize) -> Vec<f32> {
    if dims == 0 {
        return features;
    }
    for row in features.chunks_exact_mut(dims) {
        let norm = row
            .iter()
            .map(|&v| f64::from(v) * f64::from(v))
            .sum::<f64>()
            .sqrt();
        if norm > 0.0 {
            for value in row {
                *value = (f64::from(*value) / norm) as f32;
            }
        }
    }
    features
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_scaled_to_unit_length_and_zero_rows_stay() {
        let rows = normalised_rows(vec![3.0, 4.0, 0.0, 0.0, -2.0, 0.0], 2);
        assert_eq!(rows, vec![0.6, 0.8, 0.0, 0.0, -1.0, 0.0]);
    }
}
