//! What the pipeline's stages read from the stages before them: `decompose`'s face-to-part map,
//! `infer`'s model answers, `ground`'s grounding and `verify`'s verification.

use uniphys_pipeline::{ModelAnswers, RunOptions};
use uniphys_types::{GroundedAsset, ServiceStage, VerifiedAsset};

use crate::source::SourceFile;
use crate::stage::{StageError, StageInput};

/// The file `convert` and `ground` read from `decompose`'s output.
pub const FACE_PARTS_FILE: &str = "face_parts.json";
/// The file `ground` reads from `infer`'s output.
pub const INFERRED_FILE: &str = "inferred.json";
/// The file `verify` and `convert` read from `ground`'s output.
pub const GROUNDED_FILE: &str = "grounded.json";
/// The file `convert` reads from `verify`'s output.
pub const VERIFIED_FILE: &str = "verified.json";

/// What a stage running the in-process pipeline starts from: the submitted file (after checking
/// that `ingest` read it) and `options` with the parts of an upstream `decompose`, when it split
/// the input.
pub(crate) fn pipeline_start(
    input: &StageInput,
    options: &RunOptions,
) -> Result<(SourceFile, RunOptions), StageError> {
    input.upstream(ServiceStage::Ingest.name())?;
    let source = SourceFile::fetch(input)?;
    let mut options = options.clone();
    options.face_parts = stored_face_parts(input)?;
    Ok((source, options))
}

/// The face-to-part map written by an upstream `decompose` stage, if the job has one and it
/// split the input.
fn stored_face_parts(input: &StageInput) -> Result<Option<Vec<u32>>, StageError> {
    read_upstream(input, ServiceStage::Decompose, FACE_PARTS_FILE)
}

/// What an upstream `ground` stage decided, if the job has one; checked as it is read.
pub(crate) fn stored_grounding(input: &StageInput) -> Result<Option<GroundedAsset>, StageError> {
    read_checked(
        input,
        ServiceStage::Ground,
        GROUNDED_FILE,
        GroundedAsset::checked,
    )
}

/// The answers an upstream `infer` stage received, if the job has one and a server answered
/// (checked against the parts when grounding applies them).
pub(crate) fn stored_answers(input: &StageInput) -> Result<Option<ModelAnswers>, StageError> {
    read_upstream(input, ServiceStage::Infer, INFERRED_FILE)
}

/// What an upstream `verify` stage decided, if the job has one; checked as it is read.
pub(crate) fn stored_verification(input: &StageInput) -> Result<Option<VerifiedAsset>, StageError> {
    read_checked(
        input,
        ServiceStage::Verify,
        VERIFIED_FILE,
        VerifiedAsset::checked,
    )
}

/// [`read_upstream`], then `check`ed: a stored value this build cannot use fails the stage for
/// good, naming the file.
fn read_checked<T: serde::de::DeserializeOwned>(
    input: &StageInput,
    stage: ServiceStage,
    file: &str,
    check: impl FnOnce(T) -> uniphys_types::TypesResult<T>,
) -> Result<Option<T>, StageError> {
    read_upstream(input, stage, file)?
        .map(check)
        .transpose()
        .map_err(|e| StageError::Permanent(format!("{file} of stage {stage}: {e}")))
}

/// The JSON file `file` of upstream stage `stage`, if the job has that stage and it wrote it.
fn read_upstream<T: serde::de::DeserializeOwned>(
    input: &StageInput,
    stage: ServiceStage,
    file: &str,
) -> Result<Option<T>, StageError> {
    let Some((_, manifest)) = input.upstream.iter().find(|(name, _)| name == stage.name()) else {
        return Ok(None);
    };
    let Some(entry) = manifest.artifact(file) else {
        return Ok(None);
    };
    let bytes = input.fetch(&entry.key)?;
    serde_json::from_slice(&bytes)
        .map(Some)
        .map_err(|e| StageError::Permanent(format!("{}: {e}", entry.key)))
}
