//! One movable part's articulation request: candidates from its contact, the axis and pivot
//! renders, the request with its repair turn, and the model's choice mapped onto the
//! candidates. Failures of this part alone are reported, not fatal; transport and budget
//! failures stop the stage.

use std::time::Instant;

use serde_json::Value;
use uniphys_geometry::DVec3;
use uniphys_lvlm::{ChatRequest, CostLedger, LvlmClient};
use uniphys_types::PartProperties;

use crate::AnnotateError;
use crate::articulation::{CENTROID_PIVOT, Choice, candidates_for, resolve_choice};
use crate::ask::{Asked, ask_validated};
use crate::motion_graph::MovablePart;
use crate::prompt::{ArticulationContext, articulation_prompt};
use crate::schema::{ArticulationAnswer, PropertiesAnswer};
use crate::stage::{AnnotateInput, AnnotateOptions};
use crate::validate::{Violation, validate_articulation};
use crate::views::{AXIS_LEGEND, PIVOT_LEGEND, Scene, names};

/// Why a part's joint was not chosen.
pub(crate) enum PartError {
    /// The stage cannot go on (budget, transport): returned as the stage's error.
    Fatal(AnnotateError),
    /// This part's joint could not be chosen.
    Failed(String),
}

/// The result of one part, with its render time.
pub(crate) struct PartOutcome {
    pub(crate) label: u32,
    pub(crate) render_secs: f64,
    pub(crate) images: usize,
    pub(crate) result: Result<(Choice, Vec<Violation>), PartError>,
}

/// What every part's request needs.
pub(crate) struct Context<'a> {
    pub(crate) input: &'a AnnotateInput<'a>,
    pub(crate) scene: &'a Scene<'a>,
    pub(crate) composites: &'a [Vec<u8>],
    pub(crate) answer: &'a PropertiesAnswer,
    pub(crate) parts: &'a [PartProperties],
    pub(crate) client: &'a LvlmClient,
    pub(crate) ledger: &'a CostLedger,
    pub(crate) options: &'a AnnotateOptions,
    pub(crate) diagonal_m: f64,
}

impl Context<'_> {
    /// Chooses the joint of `movable`; never panics the caller, failures are in the outcome.
    pub(crate) fn articulate(&self, movable: &MovablePart) -> PartOutcome {
        let mut outcome = PartOutcome {
            label: movable.label,
            render_secs: 0.0,
            images: 0,
            result: Err(PartError::Failed(String::new())),
        };
        outcome.result = self.choose(movable, &mut outcome.render_secs, &mut outcome.images);
        outcome
    }

    fn choose(
        &self,
        movable: &MovablePart,
        render_secs: &mut f64,
        images: &mut usize,
    ) -> Result<(Choice, Vec<Violation>), PartError> {
        let index = (movable.label as usize).saturating_sub(1);
        let revolute = movable.kind == uniphys_types::JointKind::Revolute;
        let started = Instant::now();
        let candidates = candidates_for(
            movable,
            self.input.part_meshes,
            self.diagonal_m,
            self.options.points_per_part,
            self.options.seed,
        )
        .map_err(|e| PartError::Failed(format!("no articulation candidates: {e}")))?;
        let (Ok(axes), Ok(pivots)) = (
            <[DVec3; 10]>::try_from(candidates.axes.as_slice()),
            <[DVec3; 6]>::try_from(candidates.pivots.as_slice()),
        ) else {
            return Err(PartError::Failed(format!(
                "expected 10 axis and 6 pivot candidates, got {} and {}",
                candidates.axes.len(),
                candidates.pivots.len()
            )));
        };
        let anchor = pivots[CENTROID_PIVOT];
        let mut pngs = vec![
            self.composites.get(index).cloned().unwrap_or_default(),
            self.scene
                .axis_views(index, &axes, anchor)
                .map_err(PartError::Fatal)?,
        ];
        if revolute {
            pngs.push(
                self.scene
                    .pivot_views(index, &pivots)
                    .map_err(PartError::Fatal)?,
            );
        }
        *render_secs += started.elapsed().as_secs_f64();
        *images += pngs.len() - 1;

        let axis_names = names(&AXIS_LEGEND);
        let pivot_names = names(&PIVOT_LEGEND);
        let axes: Vec<(&str, [f64; 3])> = axis_names
            .iter()
            .zip(&candidates.axes)
            .map(|(name, v)| (*name, v.to_array()))
            .collect();
        let part_name = self.answer.parts.get(index).map_or("", |p| p.name.as_str());
        let default_descriptions = uniphys_types::Descriptions::default();
        let descriptions = self
            .parts
            .get(index)
            .map_or(&default_descriptions, |p| &p.descriptions);
        let prompt = articulation_prompt(&ArticulationContext {
            label: movable.label,
            part_name,
            object_name: &self.answer.object_name,
            revolute,
            descriptions,
            axes,
            pivots: pivot_names.to_vec(),
        });
        let request = ChatRequest {
            system: prompt.system,
            user_text: prompt.user_text,
            images_png: pngs,
            purpose: "articulation".into(),
        };
        let subject = format!("articulation of part {}", movable.label);
        let validate = |v: &Value| validate_articulation(v, revolute, &axis_names, &pivot_names);
        let asked: Asked<ArticulationAnswer> =
            match ask_validated(self.client, self.ledger, &request, &subject, &validate) {
                Ok(asked) => asked,
                Err(AnnotateError::InvalidAnswer { violations, .. }) => {
                    return Err(PartError::Failed(format!(
                        "the answer is invalid after a repair turn: {}",
                        violations
                            .iter()
                            .map(ToString::to_string)
                            .collect::<Vec<_>>()
                            .join("; ")
                    )));
                }
                Err(other) => return Err(PartError::Fatal(other)),
            };
        let choice = resolve_choice(
            &candidates,
            &asked.answer,
            revolute,
            &axis_names,
            &pivot_names,
        )
        .ok_or_else(|| PartError::Failed("the validated answer names no candidate".into()))?;
        Ok((choice, asked.repaired))
    }
}
