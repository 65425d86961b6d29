//! The stage: renders, one properties request per object, the motion graph, one articulation
//! request per movable part (all in parallel, bounded by the client's concurrency), and the
//! result in domain types.

use std::time::Instant;

use serde_json::Value;
use uniphys_geometry::{Aabb, DVec3, TriMesh};
use uniphys_lvlm::{ChatRequest, CostLedger, LedgerSummary, LvlmClient};
use uniphys_types::{Joint, ObjectProperties, PartProperties};

use crate::articulation::{fixed_joint, joint};
use crate::ask::{Asked, ask_validated};
use crate::convert::{lvlm_provenance, object_properties, part_properties, provider_name};
use crate::motion_graph::{MotionGraph, MotionIssue, motion_graph};
use crate::part_request::{Context, PartError, PartOutcome};
use crate::prompt::{PROMPT_VERSION, properties_prompt};
use crate::schema::PropertiesAnswer;
use crate::validate::{Violation, validate_properties};
use crate::views::{Scene, render_composites};
use crate::{AnnotateError, AnnotateResult};

/// Most parts one properties request carries (reference section 5: more are never annotated).
pub const MAX_PARTS: usize = 50;

/// What the stage annotates: the parts of one asset in the object frame (Z up, metres).
#[derive(Debug, Clone, Copy)]
pub struct AnnotateInput<'a> {
    /// Object name from the input (a hint for the model).
    pub object_name: &'a str,
    /// One mesh per part, object frame, metres; label `i + 1` is `part_meshes[i]`.
    pub part_meshes: &'a [TriMesh],
    /// Display colour per part, linear RGBA in [0, 1].
    pub part_colours: &'a [[f32; 4]],
    /// Part names from the input (hints for the model).
    pub part_names: &'a [String],
}

/// Options of the stage.
#[derive(Debug, Clone, PartialEq)]
pub struct AnnotateOptions {
    /// Refuse assets with more parts (at most [`MAX_PARTS`]).
    pub max_parts: usize,
    /// Side of each square render panel, pixels.
    pub panel_px: u32,
    /// Surface samples per part for the contact of a moving part with its parent.
    pub points_per_part: usize,
    /// Seed of the sampling, plane fit and clustering.
    pub seed: u64,
    /// Offer the input's part names to the model as hints.
    pub offer_part_names: bool,
    /// When a part's articulation answer is still invalid after its repair turn: `false` (the
    /// default) fails the stage with the reason; `true` fixes the part to its parent and lists
    /// it in [`Annotation::articulation_failures`] (dataset builds that keep partial results).
    pub fix_unanswered_parts: bool,
}

impl Default for AnnotateOptions {
    fn default() -> Self {
        Self {
            max_parts: MAX_PARTS,
            panel_px: 384,
            points_per_part: 1500,
            seed: 42,
            offer_part_names: true,
            fix_unanswered_parts: false,
        }
    }
}

/// A request whose first answer broke the schema and was repaired.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Repair {
    /// `properties` or `articulation of part <label>`.
    pub subject: String,
    /// The first answer's violations.
    pub violations: Vec<String>,
}

/// A movable part whose joint could not be chosen (it is fixed to its parent instead).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct ArticulationFailure {
    /// Its label (part index + 1).
    pub label: u32,
    /// Why.
    pub reason: String,
}

/// Wall and CPU times of the stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct AnnotateTimings {
    /// Time spent rendering and encoding images (summed over threads), seconds.
    pub render_secs: f64,
    /// Images rendered.
    pub images: usize,
    /// Wall time of the properties request (with its repair), seconds.
    pub properties_request_secs: f64,
    /// Wall time of the articulation phase (all parts in parallel), seconds.
    pub articulation_secs: f64,
}

/// Everything the stage produced.
#[derive(Debug, Clone)]
pub struct Annotation {
    /// `lvlm:<model>`, as in the provenance of every value.
    pub provider: String,
    /// The model that answered.
    pub model: String,
    /// Prompt version of the requests.
    pub prompt_version: &'static str,
    /// Object properties.
    pub object: ObjectProperties,
    /// Part properties, by part index.
    pub parts: Vec<PartProperties>,
    /// Part names the model gave, by part index.
    pub part_names: Vec<String>,
    /// Joints of the movable parts and fixed joints of their co-moving groups (`PartId(i)` is
    /// part index `i`); parts not named here are left for the caller's tree (e.g. fixed to the
    /// root).
    pub joints: Vec<Joint>,
    /// Inconsistencies of the model's neighbour relations.
    pub motion_issues: Vec<MotionIssue>,
    /// Answers that were repaired.
    pub repairs: Vec<Repair>,
    /// Movable parts whose joint could not be chosen.
    pub articulation_failures: Vec<ArticulationFailure>,
    /// Cost, tokens and calls of this asset.
    pub cost: LedgerSummary,
    /// Times.
    pub timings: AnnotateTimings,
}

fn check_input(input: &AnnotateInput<'_>, options: &AnnotateOptions) -> AnnotateResult<()> {
    let n = input.part_meshes.len();
    if n == 0 {
        return Err(AnnotateError::NoParts);
    }
    if input.part_colours.len() != n || input.part_names.len() != n {
        return Err(AnnotateError::InputMismatch {
            meshes: n,
            colours: input.part_colours.len(),
            names: input.part_names.len(),
        });
    }
    let max = options.max_parts.min(MAX_PARTS);
    if n > max {
        return Err(AnnotateError::TooManyParts { parts: n, max });
    }
    if options.panel_px < 32 || options.points_per_part < 16 {
        return Err(AnnotateError::InvalidOption {
            name: "panel_px / points_per_part",
            reason: "panels of at least 32 px and at least 16 points per part".into(),
        });
    }
    Ok(())
}

/// Annotates one asset: properties of the object and its parts, and the joints of its movable
/// parts, every request charged to `ledger`.
///
/// # Errors
/// [`AnnotateError::TooManyParts`] and the other input errors before anything is sent;
/// [`AnnotateError::Lvlm`] when the client gives up (transport, budget);
/// [`AnnotateError::InvalidAnswer`] when the properties answer is still invalid after its
/// repair turn; [`AnnotateError::ArticulationFailed`] when an articulation answer is, unless
/// [`AnnotateOptions::fix_unanswered_parts`] fixes that part to its parent instead.
pub fn annotate(
    input: &AnnotateInput<'_>,
    client: &LvlmClient,
    ledger: &CostLedger,
    options: &AnnotateOptions,
) -> AnnotateResult<Annotation> {
    check_input(input, options)?;
    let n = input.part_meshes.len();
    let mut timings = AnnotateTimings::default();
    let scene = Scene::new(input.part_meshes, input.part_colours, options.panel_px);
    let (composites, composite_secs) = render_composites(&scene, n)?;
    timings.render_secs += composite_secs;
    timings.images += n;

    let prompt = properties_prompt(
        n,
        options
            .offer_part_names
            .then_some((input.object_name, input.part_names)),
    );
    let request = ChatRequest {
        system: prompt.system,
        user_text: prompt.user_text,
        images_png: composites.clone(),
        purpose: "properties".into(),
    };
    let started = Instant::now();
    let validate = |v: &Value| validate_properties(v, n);
    let asked: Asked<PropertiesAnswer> =
        ask_validated(client, ledger, &request, "properties", &validate)?;
    timings.properties_request_secs = started.elapsed().as_secs_f64();
    let model = asked.model.clone();
    let mut repairs = Vec::new();
    note_repair(&mut repairs, "properties", &asked.repaired);
    let answer = asked.answer;

    let parts: Vec<PartProperties> = answer
        .parts
        .iter()
        .map(|p| part_properties(p, &model))
        .collect();
    let bounds = input
        .part_meshes
        .iter()
        .fold(Aabb::EMPTY, |b, m| b.union(m.bounds()));
    let object = object_properties(&answer, bounds.extents().to_array(), &model);
    let graph = motion_graph(&answer);

    let started = Instant::now();
    let context = Context {
        input,
        scene: &scene,
        composites: &composites,
        answer: &answer,
        parts: &parts,
        client,
        ledger,
        options,
        diagonal_m: bounds.diagonal(),
    };
    let outcomes: Vec<PartOutcome> = std::thread::scope(|s| {
        let handles: Vec<_> = graph
            .movable
            .iter()
            .map(|m| s.spawn(|| context.articulate(m)))
            .collect();
        handles
            .into_iter()
            .zip(&graph.movable)
            .map(|(h, m)| {
                h.join().unwrap_or_else(|_| PartOutcome {
                    label: m.label,
                    render_secs: 0.0,
                    images: 0,
                    result: Err(PartError::Failed("the articulation thread panicked".into())),
                })
            })
            .collect()
    });
    timings.articulation_secs = started.elapsed().as_secs_f64();

    let provenance = lvlm_provenance(&model);
    let mut joints = Vec::new();
    let mut failures = Vec::new();
    for (outcome, movable) in outcomes.into_iter().zip(&graph.movable) {
        timings.render_secs += outcome.render_secs;
        timings.images += outcome.images;
        match outcome.result {
            Ok((choice, repaired)) => {
                note_repair(
                    &mut repairs,
                    &format!("articulation of part {}", movable.label),
                    &repaired,
                );
                joints.push(joint(movable, &choice, provenance.clone()));
            }
            Err(PartError::Fatal(error)) => return Err(error),
            Err(PartError::Failed(reason)) if !options.fix_unanswered_parts => {
                return Err(AnnotateError::ArticulationFailed {
                    label: outcome.label,
                    reason,
                });
            }
            Err(PartError::Failed(reason)) => {
                failures.push(ArticulationFailure {
                    label: outcome.label,
                    reason,
                });
                joints.push(fixed_joint(
                    movable.parent,
                    movable.label,
                    centre(input.part_meshes, movable.label),
                    provenance.clone(),
                ));
            }
        }
    }
    joints.extend(group_links(&graph, input.part_meshes, &provenance));

    Ok(Annotation {
        provider: provider_name(&model),
        model,
        prompt_version: PROMPT_VERSION,
        object,
        parts,
        part_names: answer.parts.iter().map(|p| p.name.clone()).collect(),
        joints,
        motion_issues: graph.issues,
        repairs,
        articulation_failures: failures,
        cost: ledger.summary(),
        timings,
    })
}

fn note_repair(repairs: &mut Vec<Repair>, subject: &str, violations: &[Violation]) {
    if !violations.is_empty() {
        repairs.push(Repair {
            subject: subject.to_owned(),
            violations: violations.iter().map(ToString::to_string).collect(),
        });
    }
}

fn centre(meshes: &[TriMesh], label: u32) -> DVec3 {
    meshes
        .get((label as usize).saturating_sub(1))
        .map_or(DVec3::ZERO, |m| m.bounds().center())
}

fn group_links(
    graph: &MotionGraph,
    meshes: &[TriMesh],
    provenance: &uniphys_types::Provenance,
) -> Vec<Joint> {
    graph
        .fixed
        .iter()
        .map(|link| {
            fixed_joint(
                link.parent,
                link.child,
                centre(meshes, link.child),
                provenance.clone(),
            )
        })
        .collect()
}
