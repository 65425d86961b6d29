//! What the service's `convert` stage reports of one asset (its manifest's summary), written by
//! the worker and read back by the API's batch statistics: one type on both sides.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::AssetRecord;

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
