//! What the service's stages report of one asset (their manifests' summaries), written by the
//! worker and read back by the API's batch statistics and the worker's own tests: one type per
//! stage on both sides. `ingest` reports the file it read ([`IngestSummary`]), `decompose`
//! whether and how it split the mesh ([`DecomposeStageSummary`]), `infer` whether a model answered
//! ([`InferSummary`]), `ground` what grounding decided
//! ([`GroundSummary`]), `verify` what its checks found ([`VerifySummary`]), `convert` the finished
//! asset ([`ConvertSummary`]).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::AssetRecord;

/// The `ingest` stage's summary of one source file: its `summary.json`, and (with the warnings
/// cut to the first few, [`IngestSummary::for_manifest`]) its manifest's summary.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct IngestSummary {
    /// The submitted file's name.
    pub file: String,
    /// Parts as read.
    pub parts: usize,
    /// Triangles as read.
    pub triangles: usize,
    /// Joints the file declares.
    pub declared_joints: usize,
    /// Triangles dropped as degenerate.
    pub dropped_degenerate_triangles: usize,
    /// What the reader warned of (missing textures, ...), named by their place in the asset's
    /// folder; in the manifest only the first few.
    pub warnings: Vec<String>,
    /// How many warnings there were, when `warnings` holds only the first few (the manifest).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning_count: Option<usize>,
}

impl IngestSummary {
    /// The summary as a run's manifest carries it: the warnings' count and the first
    /// `max_warnings` (a URDF folder can warn hundreds of times, one per missing texture, and a
    /// manifest stays small).
    #[must_use]
    pub fn for_manifest(&self, max_warnings: usize) -> Self {
        Self {
            warnings: self.warnings.iter().take(max_warnings).cloned().collect(),
            warning_count: Some(self.warnings.len()),
            ..self.clone()
        }
    }
}

/// The `decompose` stage's summary of one asset: whether it split the mesh into parts, how many,
/// and who found them; or why the input kept its own parts.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DecomposeStageSummary {
    /// The mesh was split into parts (false: the input keeps its own).
    pub decomposed: bool,
    /// Parts after the stage.
    pub parts: usize,
    /// Parts of the input, when it was decomposed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub input_parts: Option<usize>,
    /// Why the input kept its parts, when it was not decomposed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Who segmented the views (the provider's name), when it was decomposed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub segmenter: Option<String>,
    /// Who generated the part candidates, when it was decomposed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub generator: Option<String>,
    /// Seconds the decomposition took, when it ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub secs: Option<f64>,
}

/// The `infer` stage's summary of one asset: which UniPhysGen model answered, if one was asked.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct InferSummary {
    /// The object-level checkpoint that answered; `None` when no server is configured (the
    /// stage stored nothing, and `ground` grounds without the model).
    pub model: Option<String>,
    /// Parts the model answered for.
    pub parts: usize,
}

/// The `ground` stage's summary of one asset: what the grounders decided, before verification.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct GroundSummary {
    /// The asset's name.
    pub name: String,
    /// Object category, as grounded.
    pub category: String,
    /// Parts grounded.
    pub parts: usize,
    /// Joints that move (fixed ones left out).
    pub movable_joints: usize,
    /// Who grounded the parts' materials, the category and the joints: providers by name
    /// (`builtin-grounder`, a model's name), other sources by label (`rule:...`), each once.
    pub grounded_by: Vec<String>,
}

/// The `verify` stage's summary of one asset: its joints' sweeps and the other checks.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct VerifySummary {
    /// Movable joints swept.
    pub joints_swept: usize,
    /// Joints that passed their sweep as grounded.
    pub joints_passed: usize,
    /// Joints replaced by a correction that passed.
    pub joints_corrected: usize,
    /// Whether the intrinsic checks (levels 0-4) passed.
    pub intrinsic_passed: bool,
    /// Whether every verification section passed (the asset is exported either way).
    pub passed: bool,
}

/// The `convert` stage's summary of one asset. Every field has a default, so a summary written
/// by an older stage version (without `dataset`) still reads.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ConvertSummary {
    /// Every check of the verification report passed.
    pub passed: bool,
    /// The asset's name.
    pub name: String,
    /// Parts of the record.
    pub parts: usize,
    /// Joints of the record (fixed ones included).
    pub joints: usize,
    /// Files written.
    pub files: usize,
    /// Seconds per pipeline stage, by stage name.
    pub stage_secs: BTreeMap<String, f64>,
    /// What a batch's dataset statistics count of this asset; `None` from older stage versions.
    pub dataset: Option<DatasetFacts>,
}

/// What a batch's dataset statistics count of one asset: its category, mass and size, its parts
/// by material category and its joints by kind.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DatasetFacts {
    /// Object category.
    pub category: String,
    /// Object mass, kg.
    pub mass_kg: f64,
    /// Object dimensions, metres.
    pub size_m: [f64; 3],
    /// Parts by material category (`wood`, `metal`, ...).
    pub materials: BTreeMap<String, u64>,
    /// Joints by kind (`revolute`, `prismatic`, `continuous`, `fixed`).
    pub joint_types: BTreeMap<String, u64>,
}

impl DatasetFacts {
    /// The facts of a finished record.
    #[must_use]
    pub fn of(record: &AssetRecord) -> Self {
        let mut materials = BTreeMap::new();
        for part in &record.parts {
            let name = part.properties.material.value.category.as_str();
            *materials.entry(name.to_owned()).or_default() += 1;
        }
        let mut joint_types = BTreeMap::new();
        for joint in &record.joints {
            *joint_types
                .entry(joint.kind.as_str().to_owned())
                .or_default() += 1;
        }
        Self {
            category: record.object.category.value.clone(),
            mass_kg: record.object.mass_kg.value,
            size_m: record.object.dimensions_m.value,
            materials,
            joint_types,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ingest_manifest_keeps_the_count_and_the_first_warnings() {
        let summary = IngestSummary {
            file: "mobility.urdf".into(),
            parts: 3,
            warnings: (0..8).map(|i| format!("texture {i} is missing")).collect(),
            ..IngestSummary::default()
        };
        let written = serde_json::to_value(&summary).expect("json");
        assert!(written.get("warning_count").is_none(), "{written}");
        let manifest = summary.for_manifest(5);
        assert_eq!(manifest.warning_count, Some(8));
        assert_eq!(manifest.warnings, summary.warnings[..5]);
        let read: IngestSummary =
            serde_json::from_value(serde_json::to_value(&manifest).expect("json")).expect("read");
        assert_eq!(read, manifest);
    }

    #[test]
    fn a_decompose_summary_names_only_what_happened() {
        let kept = DecomposeStageSummary {
            decomposed: false,
            parts: 2,
            reason: Some("kept the input's 2 parts".into()),
            ..DecomposeStageSummary::default()
        };
        let written = serde_json::to_value(&kept).expect("json");
        let keys: Vec<&str> = written
            .as_object()
            .expect("object")
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(keys, ["decomposed", "parts", "reason"]);
        let read: DecomposeStageSummary = serde_json::from_value(written).expect("read");
        assert_eq!(read, kept);
    }
}
