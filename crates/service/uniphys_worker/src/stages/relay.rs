//! The in-process pipeline's progress relayed to a queue run's: each pipeline stage the run goes
//! through is an equal share of it.

use std::time::Duration;

use uniphys_pipeline::{Progress, Stage as PipelineStage};

use crate::stage::StageControl;

/// Relays the progress of the pipeline stages in `stages` (in run order) to `control`.
pub(crate) struct Relay<'a> {
    control: &'a StageControl,
    stages: &'a [PipelineStage],
}

impl<'a> Relay<'a> {
    /// A relay for a run that goes through `stages`.
    pub(crate) fn new(control: &'a StageControl, stages: &'a [PipelineStage]) -> Self {
        Self { control, stages }
    }

    fn share(&self) -> f64 {
        1.0 / self.stages.len().max(1) as f64
    }

    fn position(&self, stage: PipelineStage) -> f64 {
        let index = self.stages.iter().position(|s| *s == stage).unwrap_or(0);
        index as f64 * self.share()
    }
}

impl Progress for Relay<'_> {
    fn stage_started(&self, stage: PipelineStage) {
        self.control.progress(self.position(stage), stage.name());
    }

    fn stage_advanced(&self, stage: PipelineStage, done: usize, total: usize) {
        let within = done as f64 / total.max(1) as f64;
        self.control.progress(
            self.position(stage) + within * self.share(),
            format!("{} {done}/{total}", stage.name()),
        );
    }

    fn stage_finished(&self, _: PipelineStage, _: Duration, _: &str) {}
}
