//! What the pipeline's stages read from the stages before them: `ingest`'s stored asset (the
//! source is parsed once, by `ingest`), `decompose`'s face-to-part map, `infer`'s model
//! answers, `ground`'s grounding and `verify`'s verification.

use uniphys_pipeline::{AssetSource, IngestedAsset, ModelAnswers, PipelineError, RunOptions};
use uniphys_types::{GroundedAsset, ServiceStage, VerifiedAsset};

use crate::source::SourceFile;
use crate::stage::{StageError, StageInput};

/// The file `ingest` writes: what it read ([`IngestedAsset`]), which later stages read instead
/// of the source.
pub const INGESTED_FILE: &str = "asset.bin";
/// The file `convert` and `ground` read from `decompose`'s output.
pub const FACE_PARTS_FILE: &str = "face_parts.json";
/// The file `ground` reads from `infer`'s output.
pub const INFERRED_FILE: &str = "inferred.json";
/// The file `verify` and `convert` read from `ground`'s output.
pub const GROUNDED_FILE: &str = "grounded.json";
/// The file `convert` reads from `verify`'s output.
pub const VERIFIED_FILE: &str = "verified.json";

/// The asset a stage works on: what `ingest` stored, or, in a job whose `ingest` ran before
/// it stored what it read, the submitted file fetched to be parsed again.
pub(crate) enum StageAsset {
    /// What `ingest` read.
    Stored(IngestedAsset),
    /// The submitted file (an older job).
    Fetched(SourceFile),
}

impl StageAsset {
    /// What `ingest` stored, else the submitted file (after checking that `ingest` ran).
    pub(crate) fn of(input: &StageInput) -> Result<Self, StageError> {
        input.upstream(ServiceStage::Ingest.name())?;
        match read_upstream_bytes(input, ServiceStage::Ingest, INGESTED_FILE)? {
            Some((key, bytes)) => IngestedAsset::from_bytes(&bytes)
                .map(Self::Stored)
                .map_err(|e| StageError::Permanent(format!("{key}: {e}"))),
            None => SourceFile::fetch(input).map(Self::Fetched),
        }
    }

    /// The pipeline's view of it.
    pub(crate) fn source(&self) -> AssetSource<'_> {
        match self {
            Self::Stored(asset) => AssetSource::Ingested(asset),
            Self::Fetched(file) => AssetSource::File(file.path()),
        }
    }

    /// The stage error for a pipeline failure on this asset, told without the worker's
    /// temporary folder: a failure the same run may get past later
    /// ([`PipelineError::is_transient`]: a model server that stayed away) is retried.
    pub(crate) fn failed(&self, error: &PipelineError) -> StageError {
        let message = self.without_local_paths(&format!("the pipeline failed: {error}"));
        if error.is_transient() {
            StageError::Transient(message)
        } else {
            StageError::Permanent(message)
        }
    }

    /// `message` without the worker's temporary folder ([`SourceFile::without_local_paths`]);
    /// a stored asset names none.
    pub(crate) fn without_local_paths(&self, message: &str) -> String {
        match self {
            Self::Stored(_) => message.to_owned(),
            Self::Fetched(file) => file.without_local_paths(message),
        }
    }

    /// An output file's bytes without the worker's temporary folder
    /// ([`SourceFile::without_local_paths_in`]).
    pub(crate) fn without_local_paths_in(&self, name: &str, bytes: Vec<u8>) -> Vec<u8> {
        match self {
            Self::Stored(_) => bytes,
            Self::Fetched(file) => file.without_local_paths_in(name, bytes),
        }
    }
}

/// What a stage running the in-process pipeline starts from: the asset ([`StageAsset::of`])
/// and `options` with the parts of an upstream `decompose`, when it split the input.
pub(crate) fn pipeline_start(
    input: &StageInput,
    options: &RunOptions,
) -> Result<(StageAsset, RunOptions), StageError> {
    let asset = StageAsset::of(input)?;
    let mut options = options.clone();
    options.face_parts = stored_face_parts(input)?;
    Ok((asset, options))
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
    let Some((key, bytes)) = read_upstream_bytes(input, stage, file)? else {
        return Ok(None);
    };
    serde_json::from_slice(&bytes)
        .map(Some)
        .map_err(|e| StageError::Permanent(format!("{key}: {e}")))
}

/// The key and bytes of file `file` of upstream stage `stage`, if the job has that stage and it
/// wrote it.
fn read_upstream_bytes(
    input: &StageInput,
    stage: ServiceStage,
    file: &str,
) -> Result<Option<(String, Vec<u8>)>, StageError> {
    let Some((_, manifest)) = input.upstream.iter().find(|(name, _)| name == stage.name()) else {
        return Ok(None);
    };
    let Some(entry) = manifest.artifact(file) else {
        return Ok(None);
    };
    let bytes = input.fetch(&entry.key)?;
    Ok(Some((entry.key.clone(), bytes)))
}
