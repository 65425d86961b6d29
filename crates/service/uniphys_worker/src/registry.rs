//! Which stages a worker binary knows, and the stage graph a submitted asset gets.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use uniphys_queue::{JobSpec, StageSpec};
use uniphys_types::ServiceStage;

use crate::stage::Stage;
use crate::stages::{
    ConvertStage, DecomposeStage, GroundStage, InferStage, IngestStage, StandInStage, VerifyStage,
};

/// Stages by name.
#[derive(Clone, Default)]
pub struct StageRegistry {
    stages: BTreeMap<String, Arc<dyn Stage>>,
}

impl std::fmt::Debug for StageRegistry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.stages.keys()).finish()
    }
}

impl StageRegistry {
    /// The real pipeline with default options: `ingest`, `decompose` (auto), `infer`, `ground`,
    /// `verify` and `convert`.
    #[must_use]
    pub fn pipeline() -> Self {
        Self::pipeline_with(DecomposeStage::default(), ConvertStage::default())
    }

    /// The real pipeline with the given `decompose` and `convert` stages (their options: the
    /// decomposition mode, an LVLM or a UniPhysGen server, verification parameters). `infer`,
    /// `ground` and `verify` run with `convert`'s options; `infer` alone calls the UniPhysGen
    /// server and `ground` alone the LVLM;
    /// `convert`'s reader options are used by `ingest` and `decompose` too, so every stage sees
    /// the same faces.
    #[must_use]
    pub fn pipeline_with(decompose: DecomposeStage, convert: ConvertStage) -> Self {
        let ingest = convert.options.ingest.clone();
        Self::default()
            .with(IngestStage {
                options: ingest.clone(),
            })
            .with(DecomposeStage {
                ingest,
                ..decompose
            })
            .with(InferStage {
                options: convert.options.clone(),
            })
            .with(GroundStage {
                options: convert.options.clone(),
            })
            .with(VerifyStage {
                options: convert.options.clone(),
            })
            .with(convert)
    }

    /// Deterministic stand-ins named `names`, each taking `work` (tests, crash tests, benches).
    #[must_use]
    pub fn stand_ins(names: &[&str], work: Duration) -> Self {
        names.iter().fold(Self::default(), |registry, name| {
            registry.with(StandInStage::new(*name, work))
        })
    }

    /// Adds (or replaces) a stage.
    #[must_use]
    pub fn with(mut self, stage: impl Stage) -> Self {
        self.stages.insert(stage.name().to_owned(), Arc::new(stage));
        self
    }

    /// The stage called `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<Arc<dyn Stage>> {
        self.stages.get(name).cloned()
    }

    /// All stage names, sorted.
    #[must_use]
    pub fn names(&self) -> Vec<String> {
        self.stages.keys().cloned().collect()
    }
}

/// Attempts of a pipeline stage before it is dead-lettered.
const PIPELINE_MAX_ATTEMPTS: u32 = 3;

/// The stage graph every submitted asset gets: `ingest` → `decompose` → `infer` → `ground` →
/// `verify` → `convert` (each later stage also reads the outputs of the earlier ones, so it
/// depends on all of them).
#[must_use]
pub fn pipeline_job_spec() -> JobSpec {
    let stages = ServiceStage::ALL
        .iter()
        .enumerate()
        .map(|(i, stage)| {
            ServiceStage::ALL[..i]
                .iter()
                .fold(StageSpec::new(stage.name()), |spec, before| {
                    spec.after(before.name())
                })
                .with_max_attempts(PIPELINE_MAX_ATTEMPTS)
        })
        .collect();
    JobSpec::new(stages)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pipeline_graph_names_only_registered_stages() {
        let registry = StageRegistry::pipeline();
        let spec = pipeline_job_spec();
        assert!(spec.validate().is_ok());
        for stage in &spec.stages {
            assert!(registry.get(&stage.name).is_some(), "{}", stage.name);
        }
        assert_eq!(
            registry.names(),
            [
                "convert",
                "decompose",
                "ground",
                "infer",
                "ingest",
                "verify"
            ]
        );
    }

    #[test]
    fn every_pipeline_stage_waits_for_every_stage_before_it() {
        let spec = pipeline_job_spec();
        let names: Vec<&str> = spec.stages.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "ingest",
                "decompose",
                "infer",
                "ground",
                "verify",
                "convert"
            ]
        );
        for (i, stage) in spec.stages.iter().enumerate() {
            let before: Vec<&str> = names[..i].to_vec();
            assert_eq!(stage.depends_on, before, "{}", stage.name);
            assert_eq!(stage.max_attempts, PIPELINE_MAX_ATTEMPTS);
        }
    }
}
