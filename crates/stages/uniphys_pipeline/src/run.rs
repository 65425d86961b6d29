//! `run`: the whole pipeline on one asset, in process; [`infer_asset`]: its stages up to the
//! UniPhysGen server's answers, [`ground_asset`]: up to grounding, and [`verify_asset`]: up to
//! verification, whose results a later `run` takes instead of asking, grounding or verifying
//! again (the queue's `infer`, `ground` and `verify` stages, then `convert`).
//!
//! Stages: ingest (`input`), infer (a UniPhysGen server's answers, when one is configured;
//! `grounding`), prepare (mass properties), colliders (convex decomposition), ground
//! (materials, properties, articulation chosen by sweeps; `grounding`), verify (intrinsic levels
//! 0-4, articulation sweeps with correction) and export (`finish`).

use std::time::{Duration, Instant};

use uniphys_decompose::{DecomposeMode, DecomposeOptions};
use uniphys_export::Artifact;
use uniphys_geometry::{ConvexParams, TriMesh};
use uniphys_mesh_io::IngestOptions;
use uniphys_types::{AssetRecord, GroundedAsset, VerificationReport, VerifiedAsset};
use uniphys_uniphysgen::ModelAnswers;

use crate::finish::{export_verified, part_meshes, verify_grounded};
use crate::grounding::{
    ask_model, colliders, ground, infer, prepare, stored_colliders, stored_grounding,
};
use crate::input::{AssetSource, Input, read_input};
use crate::learned::LearnedOptions;
use crate::lvlm::LvlmOptions;
use crate::verify::VerifyOptions;
use crate::{PipelineError, PipelineResult, Progress, Stage};

/// Options of an in-process run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// How to read the input.
    pub ingest: IngestOptions,
    /// Voxels along the longest side of a part for the volume of open meshes (reference: 128).
    pub voxel_resolution: usize,
    /// Convex decomposition parameters for the colliders.
    pub convex: ConvexParams,
    /// Parts closer than this fraction of the object diagonal count as touching (MJCF excludes).
    pub touching_fraction: f64,
    /// Ground with a UniPhysGen model server instead of the built-in grounder's estimates.
    pub learned: Option<LearnedOptions>,
    /// What an earlier run of the `infer` stage received from a UniPhysGen server
    /// ([`infer_asset`]; the queue's `infer` stage): grounding applies these answers instead of
    /// asking the server (`learned` is then not asked).
    pub inferred: Option<ModelAnswers>,
    /// Ground with an LVLM (properties, motion graph, joints chosen among candidates) after the
    /// built-in grounder; its values replace the estimates.
    pub lvlm: Option<LvlmOptions>,
    /// Verification parameters.
    pub verify: VerifyOptions,
    /// Decompose the input into parts right after ingest (built-in segmenter and generator);
    /// the decomposed parts replace the input's parts and its declared joints are dropped (they
    /// name the old parts). `None` (default) keeps the input's parts and joints.
    pub decompose: Option<DecomposeOptions>,
    /// Which inputs `decompose` applies to (`Always`: every input; `Auto`: one-piece or
    /// fragmented inputs without joints).
    pub decompose_mode: DecomposeMode,
    /// A face-to-part map of the input's merged mesh computed earlier (the queue's `decompose`
    /// stage): applied right after ingest instead of decomposing again.
    pub face_parts: Option<Vec<u32>>,
    /// What an earlier run of the `ground` stage decided ([`ground_asset`]; the queue's `ground`
    /// stage), colliders included: used instead of preparing, decomposing into hulls and grounding
    /// again, so no UniPhysGen or LVLM request is sent. It must name the parts the input is read
    /// into.
    pub grounded: Option<GroundedAsset>,
    /// What an earlier run of the `verify` stage decided ([`verify_asset`]; the queue's `verify`
    /// stage) on `grounded`, which it needs: used instead of verifying again, so only export
    /// runs.
    pub verified: Option<VerifiedAsset>,
    /// `--unit auto`: an input whose coordinates are not a length (a PartNet-Mobility folder)
    /// is scaled to the typical size of its kind, and one whose unit makes it implausible for
    /// its kind is read in the common unit that fits (see `real_scale.rs`); off when the user
    /// gave the unit (`ingest.metres_per_unit` is then used as is).
    pub unit_auto: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            ingest: IngestOptions::default(),
            voxel_resolution: 128,
            convex: ConvexParams::default(),
            touching_fraction: 0.005,
            learned: None,
            inferred: None,
            lvlm: None,
            verify: VerifyOptions::default(),
            decompose: None,
            decompose_mode: DecomposeMode::Always,
            face_parts: None,
            grounded: None,
            verified: None,
            unit_auto: true,
        }
    }
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// The annotated asset.
    pub record: AssetRecord,
    /// Exported files, sorted by path.
    pub artifacts: Vec<Artifact>,
    /// All checks that ran.
    pub report: VerificationReport,
    /// Wall time of each stage, in run order.
    pub timings: Vec<(Stage, Duration)>,
}

/// Times the stages of a run and reports them to its [`Progress`].
pub(crate) struct Clock<'a> {
    pub(crate) progress: &'a dyn Progress,
    timings: Vec<(Stage, Duration)>,
}

impl<'a> Clock<'a> {
    fn new(progress: &'a dyn Progress) -> Self {
        Self {
            progress,
            timings: Vec::new(),
        }
    }

    /// Runs stage `f`, which returns its value and a one-line summary.
    pub(crate) fn stage<T>(
        &mut self,
        stage: Stage,
        f: impl FnOnce() -> PipelineResult<(T, String)>,
    ) -> PipelineResult<T> {
        self.progress.stage_started(stage);
        let start = Instant::now();
        let (value, summary) = f()?;
        let elapsed = start.elapsed();
        self.timings.push((stage, elapsed));
        self.progress.stage_finished(stage, elapsed, &summary);
        Ok(value)
    }
}

/// Runs ingest, prepare, colliders, ground, verify and export on `source` (a file, or the asset
/// an `ingest` stage stored); with `options.grounded`, prepare, colliders and ground are skipped
/// and the stored grounding (with its colliders) is verified; with `options.verified` too, only
/// export runs.
pub fn run<'a>(
    source: impl Into<AssetSource<'a>>,
    options: &RunOptions,
    progress: &dyn Progress,
) -> PipelineResult<RunOutput> {
    let mut clock = Clock::new(progress);
    let (input, colliders, grounded) = grounded_input(source.into(), options, &mut clock)?;
    let meshes = part_meshes(&input.asset);
    let verified = match &options.verified {
        Some(stored) => stored_verification(stored, &grounded.record)?,
        None => verify_grounded(
            &input,
            &meshes,
            grounded.record,
            &colliders,
            options,
            &mut clock,
        )?,
    };
    let mut notes = input.notes.clone();
    notes.extend(grounded.notes);
    let finished = export_verified(&input, &meshes, verified, colliders, notes, &mut clock)?;
    Ok(RunOutput {
        record: finished.record,
        artifacts: finished.artifacts,
        report: finished.report,
        timings: clock.timings,
    })
}

/// Runs ingest, prepare, colliders and ground on `source` and returns what grounding decided,
/// for a later [`run`] with `options.grounded` (`options.grounded` itself is ignored).
pub fn ground_asset<'a>(
    source: impl Into<AssetSource<'a>>,
    options: &RunOptions,
    progress: &dyn Progress,
) -> PipelineResult<GroundedAsset> {
    let mut clock = Clock::new(progress);
    let input = read_input(source.into(), options, &mut clock)?;
    let (_, grounded) = ground_here(&input, options, &mut clock)?;
    Ok(grounded)
}

/// Runs ingest and infer on `source` and returns the UniPhysGen server's answers, for a later
/// [`ground_asset`] or [`run`] with `options.inferred`; `None` when no server is configured
/// (`options.learned`; `options.inferred` itself is ignored).
pub fn infer_asset<'a>(
    source: impl Into<AssetSource<'a>>,
    options: &RunOptions,
    progress: &dyn Progress,
) -> PipelineResult<Option<ModelAnswers>> {
    let mut clock = Clock::new(progress);
    let input = read_input(source.into(), options, &mut clock)?;
    ask_model(&input, options, &mut clock)
}

/// Runs ingest and verify on `source` grounded as `options.grounded` says (or, without it,
/// grounded here first) and returns what verification decided, for a later [`run`] with
/// `options.verified` (`options.verified` itself is ignored).
pub fn verify_asset<'a>(
    source: impl Into<AssetSource<'a>>,
    options: &RunOptions,
    progress: &dyn Progress,
) -> PipelineResult<VerifiedAsset> {
    let mut clock = Clock::new(progress);
    let (input, colliders, grounded) = grounded_input(source.into(), options, &mut clock)?;
    let meshes = part_meshes(&input.asset);
    verify_grounded(
        &input,
        &meshes,
        grounded.record,
        &colliders,
        options,
        &mut clock,
    )
}

/// The input read, with its colliders and grounding: stored ones when `options.grounded` has
/// them, else prepared, decomposed into hulls and grounded here.
fn grounded_input(
    source: AssetSource<'_>,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<(Input, Vec<Vec<TriMesh>>, GroundedAsset)> {
    let input = read_input(source, options, clock)?;
    let (colliders, grounded) = match &options.grounded {
        Some(stored) => {
            let grounded = stored_grounding(stored, &input.asset)?;
            (stored_colliders(&grounded)?, grounded)
        }
        None => ground_here(&input, options, clock)?,
    };
    Ok((input, colliders, grounded))
}

/// `input` grounded here: the model's answers (stored or asked), then prepare, colliders and
/// ground; its colliders and what grounding decided.
fn ground_here(
    input: &Input,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<(Vec<Vec<TriMesh>>, GroundedAsset)> {
    let answers = infer(input, options, clock)?;
    let prepared = prepare(input, options, clock)?;
    let colliders = colliders(input, options, clock)?;
    let grounded = ground(
        input,
        &prepared,
        &colliders,
        answers.as_ref(),
        options,
        clock,
    )?;
    Ok((colliders, grounded))
}

/// A verification stored by an earlier run of the `verify` stage, checked against the grounding
/// it is applied to: the same parts, by count and name.
fn stored_verification(
    verified: &VerifiedAsset,
    grounded: &AssetRecord,
) -> PipelineResult<VerifiedAsset> {
    let verified = verified.clone().checked()?;
    let names =
        |r: &AssetRecord| -> Vec<String> { r.parts.iter().map(|p| p.name.clone()).collect() };
    if names(&verified.record) != names(grounded) {
        return Err(PipelineError::StoredVerification(format!(
            "it names the parts {:?}, the grounding has {:?}",
            names(&verified.record),
            names(grounded)
        )));
    }
    Ok(verified)
}
