//! `verify`: the grounding an upstream `ground` stage stored, verified on the stored asset's
//! parts (intrinsic checks, every movable joint swept and corrected when it fails, the dynamic
//! check); writes what verification decided (`verified.json`, a [`VerifiedAsset`]), which
//! `convert` exports. It sends no model request, and a retry of `convert` verifies nothing again.

use serde_json::Value;
use uniphys_pipeline::{RunOptions, Stage as PipelineStage, verify_asset};
use uniphys_types::{ServiceStage, VerifiedAsset, VerifySummary};

use crate::outputs::{OutputWriter, summary_value};
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::relay::Relay;
use crate::stages::upstream::{VERIFIED_FILE, pipeline_start, stored_grounding};

/// The pipeline stages a `verify` run goes through after a `ground` stage.
const AFTER_GROUND: [PipelineStage; 2] = [PipelineStage::Ingest, PipelineStage::Verify];

/// The verify stage.
#[derive(Clone, Debug, Default)]
pub struct VerifyStage {
    /// Pipeline options (the reader's, the verifier's).
    pub options: RunOptions,
}

impl Stage for VerifyStage {
    fn name(&self) -> &str {
        ServiceStage::Verify.name()
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
        let (asset, mut options) = pipeline_start(input, &self.options)?;
        options.grounded = Some(stored_grounding(input)?.ok_or_else(|| {
            StageError::Permanent(
                "verify needs the grounding of an upstream ground stage, and the job has none"
                    .to_owned(),
            )
        })?);
        let verified = verify_asset(
            asset.source(),
            &options,
            &Relay::new(control, &AFTER_GROUND),
        )
        .map_err(|e| asset.failed(&e))?;
        control.check()?;
        out.put_json(VERIFIED_FILE, &verified)?;
        summary_value(&summary_of(&verified))
    }
}

/// The manifest's summary of a verification.
fn summary_of(verified: &VerifiedAsset) -> VerifySummary {
    VerifySummary {
        joints_swept: verified.joints_swept,
        joints_passed: verified.joints_passed,
        joints_corrected: verified.corrections.len(),
        intrinsic_passed: verified.intrinsic_passed,
        passed: verified.sections.iter().all(|s| s.passed()),
    }
}
