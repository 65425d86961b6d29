//! `decompose`: stage 2 in the queue. Reads the asset `ingest` stored, and when it needs it (see
//! [`DecomposeMode`]) splits it into parts with the built-in providers, or with SAM-compatible and
//! PartField-compatible services when they are configured; writes the per-part
//! meshes, `face_parts.json` (face of the merged input mesh → part) and `decompose.json`.
//! `ground` and `convert` apply `face_parts.json` to the same input, so the parts keep their
//! materials.
//! An input that keeps its own parts gets a summary only.

use serde_json::Value;
use uniphys_decompose::{
    DecomposeError, DecomposeMode, DecomposeOptions, decompose_asset, generator_for, segmenter_for,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::{DecomposeStageSummary, ServiceStage};
use uniphys_vision::ClientConfig;

use crate::input_error::unreadable;
use crate::outputs::{OutputWriter, summary_value};
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::upstream::StageAsset;

/// The decompose stage.
#[derive(Clone, Debug, Default)]
pub struct DecomposeStage {
    /// Reader options; must equal `convert`'s so the face order is the same.
    pub ingest: IngestOptions,
    /// When to decompose.
    pub mode: DecomposeMode,
    /// Views, resolution, thresholds, seed.
    pub options: DecomposeOptions,
    /// A SAM-compatible mask service; `None` for the built-in segmenter.
    pub sam: Option<ClientConfig>,
    /// A PartField-compatible feature service; `None` for the built-in geometric generator.
    pub partfield: Option<ClientConfig>,
}

/// A failure the same run may get past later ([`DecomposeError::is_transient`]) is retried.
fn classify(error: DecomposeError) -> StageError {
    let message = format!("decomposition failed: {error}");
    if error.is_transient() {
        StageError::Transient(message)
    } else {
        StageError::Permanent(message)
    }
}

impl Stage for DecomposeStage {
    fn name(&self) -> &str {
        ServiceStage::Decompose.name()
    }

    fn version(&self) -> u32 {
        // 2: reads `ingest`'s stored asset when it wrote one.
        2
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        control.progress(0.05, "reading the ingested asset");
        let asset = match StageAsset::of(input)? {
            StageAsset::Stored(stored) => stored.loaded.asset,
            StageAsset::Fetched(source) => {
                load_asset(source.path(), &self.ingest)
                    .map_err(|e| unreadable(&source, &e))?
                    .asset
            }
        };
        if !self.mode.applies_to(&asset) {
            let summary = DecomposeStageSummary {
                decomposed: false,
                parts: asset.parts.len(),
                reason: Some(format!(
                    "kept the input's {} parts ({} declared joints; mode {:?})",
                    asset.parts.len(),
                    asset.joints.len(),
                    self.mode
                )),
                ..DecomposeStageSummary::default()
            };
            out.put_json("decompose.json", &summary)?;
            return summary_value(&summary);
        }
        control.check()?;
        control.progress(0.2, "decomposing");
        let segmenter = segmenter_for(self.sam.as_ref()).map_err(classify)?;
        let generator = generator_for(self.partfield.as_ref()).map_err(classify)?;
        let (_, decomposition) = decompose_asset(
            &asset,
            segmenter.as_ref(),
            generator.as_ref(),
            &self.options,
        )
        .map_err(classify)?;
        control.check()?;
        let files = decomposition
            .files(&asset.merged())
            .map_err(|e| StageError::Permanent(format!("writing the parts: {e}")))?;
        for (path, bytes) in files {
            out.put(&path, bytes)?;
        }
        let summary = &decomposition.summary;
        summary_value(&DecomposeStageSummary {
            decomposed: true,
            parts: decomposition.part_count,
            input_parts: Some(asset.parts.len()),
            reason: None,
            segmenter: Some(summary.segmenter.clone()),
            generator: Some(summary.generator.clone()),
            secs: Some(summary.total_secs()),
        })
    }
}
