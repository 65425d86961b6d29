//! The output manifest a stage run records when it completes: which objects it wrote and a
//! small summary. Payloads stay small (ids and keys, never data; see [`crate::MAX_MANIFEST_BYTES`]).

use serde::{Deserialize, Serialize};
use serde_json::Value;

/// What a succeeded stage run wrote, stored as its `output_manifest`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputManifest {
    /// The objects written, by name.
    #[serde(default)]
    pub artifacts: Vec<ArtifactEntry>,
    /// Stage-specific facts worth showing without downloading anything (counts, verdicts).
    #[serde(default)]
    pub summary: Value,
}

/// One object a stage wrote.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArtifactEntry {
    /// Relative name under the stage's prefix, e.g. `model.urdf` or `meshes/part_1.obj`.
    pub name: String,
    /// Full object-store key.
    pub key: String,
    /// Size in bytes.
    pub bytes: u64,
    /// SHA-256 of the content, lowercase hex.
    pub sha256: String,
}

impl OutputManifest {
    /// Reads a stored manifest; `None` for a run without one or one of another shape.
    #[must_use]
    pub fn from_value(value: &Value) -> Option<Self> {
        serde_json::from_value(value.clone()).ok()
    }

    /// The manifest as stored.
    #[must_use]
    pub fn to_value(&self) -> Value {
        serde_json::to_value(self).unwrap_or(Value::Null)
    }

    /// The entry named `name`.
    #[must_use]
    pub fn artifact(&self, name: &str) -> Option<&ArtifactEntry> {
        self.artifacts.iter().find(|a| a.name == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manifest_round_trips_and_other_shapes_are_not_manifests() {
        let manifest = OutputManifest {
            artifacts: vec![ArtifactEntry {
                name: "model.urdf".into(),
                key: "1/export/v1/ab/model.urdf".into(),
                bytes: 12,
                sha256: "00".into(),
            }],
            summary: serde_json::json!({ "parts": 3 }),
        };
        let back = OutputManifest::from_value(&manifest.to_value());
        assert_eq!(back.as_ref(), Some(&manifest));
        assert_eq!(
            back.and_then(|m| m.artifact("model.urdf").map(|a| a.bytes)),
            Some(12)
        );
        assert!(OutputManifest::from_value(&serde_json::json!({ "files": [] })).is_none());
        assert_eq!(
            OutputManifest::from_value(&serde_json::json!({})),
            Some(OutputManifest::default())
        );
    }
}
