//! `ground`: the pipeline's stages up to grounding (ingest, prepare, colliders, ground) on the
//! asset `ingest` stored, split into the parts of an upstream `decompose` when it split the input,
//! with the UniPhysGen answers an upstream `infer` stored (in a job without `infer`, it asks a
//! configured server itself). The only stage that calls an LVLM; it writes what the grounders
//! decided (`grounded.json`, a [`GroundedAsset`]), which `verify` checks and `convert` exports, so
//! a retry of either asks no model again.

use std::collections::BTreeSet;

use serde_json::Value;
use uniphys_pipeline::{RunOptions, Stage as PipelineStage, ground_asset};
use uniphys_types::{AssetRecord, GroundSummary, GroundedAsset, Provenance, ServiceStage};

use crate::outputs::{OutputWriter, summary_value};
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::relay::Relay;
use crate::stages::upstream::{GROUNDED_FILE, pipeline_start, stored_answers};

/// The pipeline stages a `ground` run goes through.
const GROUND_STAGES: [PipelineStage; 4] = [
    PipelineStage::Ingest,
    PipelineStage::Prepare,
    PipelineStage::Colliders,
    PipelineStage::Ground,
];

/// The ground stage.
#[derive(Clone, Debug, Default)]
pub struct GroundStage {
    /// Pipeline options (the reader's, the models').
    pub options: RunOptions,
}

impl Stage for GroundStage {
    fn name(&self) -> &str {
        ServiceStage::Ground.name()
    }

    fn version(&self) -> u32 {
        // 2: the UniPhysGen answers come from an upstream `infer` when the job has one.
        // 3: the asset comes from `ingest`'s stored copy when it wrote one.
        3
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        let (asset, mut options) = pipeline_start(input, &self.options)?;
        options.inferred = stored_answers(input)?;
        let grounded = ground_asset(
            asset.source(),
            &options,
            &Relay::new(control, &GROUND_STAGES),
        )
        .map_err(|e| asset.failed(&e))?;
        control.check()?;
        out.put_json(GROUNDED_FILE, &grounded)?;
        summary_value(&summary_of(&grounded))
    }
}

/// The manifest's summary of a grounding.
fn summary_of(grounded: &GroundedAsset) -> GroundSummary {
    let record = &grounded.record;
    GroundSummary {
        name: record.name.clone(),
        category: record.object.category.value.clone(),
        parts: record.parts.len(),
        movable_joints: record.joints.iter().filter(|j| j.kind.is_movable()).count(),
        grounded_by: providers(record),
    }
}

/// The providers named by the provenance of the record's materials, category and joints.
fn providers(record: &AssetRecord) -> Vec<String> {
    let provenances = record
        .parts
        .iter()
        .map(|p| &p.properties.material.provenance)
        .chain([&record.object.category.provenance])
        .chain(record.joints.iter().map(|j| &j.provenance));
    let names: BTreeSet<String> = provenances
        .map(|p| match p {
            Provenance::Provider { name, .. } => name.clone(),
            other => other.label(),
        })
        .collect();
    names.into_iter().collect()
}
