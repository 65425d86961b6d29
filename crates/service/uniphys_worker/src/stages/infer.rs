//! `infer`: the UniPhysGen model server asked about the stored asset's parts (split as an
//! upstream `decompose` split them) and its object, when this worker has one configured: the only
//! stage that calls it, so its GPU slots are taken by this stage's pool alone. Writes the answers
//! (`inferred.json`, [`ModelAnswers`]), which `ground` applies without asking again; with no
//! server configured it writes nothing and `ground` grounds without the model.

use serde_json::Value;
use uniphys_pipeline::{ModelAnswers, RunOptions, Stage as PipelineStage, infer_asset};
use uniphys_types::{InferSummary, ServiceStage};

use crate::outputs::{OutputWriter, summary_value};
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::relay::Relay;
use crate::stages::upstream::{INFERRED_FILE, pipeline_start};

/// The pipeline stages an `infer` run goes through.
const INFER_STAGES: [PipelineStage; 2] = [PipelineStage::Ingest, PipelineStage::Infer];

/// The infer stage.
#[derive(Clone, Debug, Default)]
pub struct InferStage {
    /// Pipeline options (the reader's, the UniPhysGen server's).
    pub options: RunOptions,
}

impl Stage for InferStage {
    fn name(&self) -> &str {
        ServiceStage::Infer.name()
    }

    fn version(&self) -> u32 {
        // 2: the asset comes from `ingest`'s stored copy when it wrote one.
        2
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        if self.options.learned.is_none() {
            return summary_value(&InferSummary::default());
        }
        let (asset, options) = pipeline_start(input, &self.options)?;
        let answers = infer_asset(
            asset.source(),
            &options,
            &Relay::new(control, &INFER_STAGES),
        )
        .map_err(|e| asset.failed(&e))?;
        control.check()?;
        let Some(answers) = answers else {
            return summary_value(&InferSummary::default());
        };
        out.put_json(INFERRED_FILE, &answers)?;
        summary_value(&summary_of(&answers))
    }
}

/// The manifest's summary of the answers.
fn summary_of(answers: &ModelAnswers) -> InferSummary {
    InferSummary {
        model: Some(answers.object_model.clone()),
        parts: answers.physics.parts.len(),
    }
}
