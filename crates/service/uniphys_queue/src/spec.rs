//! What a job runs: its stages and their dependencies, checked before anything is stored.

use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};

use crate::{QueueError, QueueResult};

/// Attempts per stage run when a [`StageSpec`] does not say.
pub const DEFAULT_MAX_ATTEMPTS: u32 = 5;

/// The stage graph of one job; stored as the job's `dag`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct JobSpec {
    /// Higher runs first; runs of equal priority run oldest first.
    pub priority: i32,
    /// The stages; names are unique within the job.
    pub stages: Vec<StageSpec>,
    /// W3C `traceparent` of the request that submitted the job, so each stage's span joins
    /// that trace.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trace_parent: Option<String>,
}

/// One stage of a job.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageSpec {
    /// The stage name workers claim by (`ingest`, `decompose`, …).
    pub name: String,
    /// Stages of the same job that must succeed first.
    pub depends_on: Vec<String>,
    /// Attempts before the run is dead-lettered (also the budget granted by a retry).
    pub max_attempts: u32,
}

impl StageSpec {
    /// A stage with no dependencies and [`DEFAULT_MAX_ATTEMPTS`].
    #[must_use]
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            depends_on: Vec::new(),
            max_attempts: DEFAULT_MAX_ATTEMPTS,
        }
    }

    /// Adds a dependency.
    #[must_use]
    pub fn after(mut self, stage: impl Into<String>) -> Self {
        self.depends_on.push(stage.into());
        self
    }

    /// Sets the attempt budget.
    #[must_use]
    pub fn with_max_attempts(mut self, max_attempts: u32) -> Self {
        self.max_attempts = max_attempts;
        self
    }
}

impl JobSpec {
    /// A job of `stages` at priority 0.
    #[must_use]
    pub fn new(stages: Vec<StageSpec>) -> Self {
        Self {
            priority: 0,
            stages,
            trace_parent: None,
        }
    }

    /// A linear pipeline: each stage depends on the one before it.
    #[must_use]
    pub fn chain(names: &[&str]) -> Self {
        let stages = names
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let stage = StageSpec::new(*name);
                match i.checked_sub(1) {
                    Some(prev) => stage.after(names[prev]),
                    None => stage,
                }
            })
            .collect();
        Self::new(stages)
    }

    /// Sets the trace context the stages continue.
    #[must_use]
    pub fn with_trace_parent(mut self, trace_parent: Option<String>) -> Self {
        self.trace_parent = trace_parent;
        self
    }

    /// Sets the priority.
    #[must_use]
    pub fn with_priority(mut self, priority: i32) -> Self {
        self.priority = priority;
        self
    }

    /// Checks that the graph is non-empty, names are unique and non-empty, dependencies exist,
    /// every stage has at least one attempt, and there is no cycle.
    pub fn validate(&self) -> QueueResult<()> {
        let invalid = |msg: String| Err(QueueError::Invalid(msg));
        if self.stages.is_empty() {
            return invalid("a job needs at least one stage".into());
        }
        let mut names = BTreeSet::new();
        for stage in &self.stages {
            if stage.name.is_empty() || stage.name.len() > 100 {
                return invalid(format!(
                    "stage name must be 1 to 100 bytes, got {:?}",
                    stage.name
                ));
            }
            if stage.max_attempts == 0 {
                return invalid(format!("stage {} needs max_attempts >= 1", stage.name));
            }
            if !names.insert(stage.name.as_str()) {
                return invalid(format!("stage {} appears twice", stage.name));
            }
        }
        for stage in &self.stages {
            for dep in &stage.depends_on {
                if !names.contains(dep.as_str()) {
                    return invalid(format!(
                        "stage {} depends on unknown stage {dep}",
                        stage.name
                    ));
                }
            }
        }
        if let Some(tp) = &self.trace_parent
            && (tp.len() > 256 || !tp.chars().all(|c| c.is_ascii_graphic()))
        {
            return invalid("trace_parent must be at most 256 printable ASCII characters".into());
        }
        if self.topological_order().len() != self.stages.len() {
            return invalid("the stage graph has a cycle".into());
        }
        Ok(())
    }

    /// Stage names in an order where dependencies come first (Kahn's algorithm, ties by name);
    /// shorter than `stages` when there is a cycle.
    #[must_use]
    pub fn topological_order(&self) -> Vec<&str> {
        let mut waiting: BTreeMap<&str, usize> = self
            .stages
            .iter()
            .map(|s| (s.name.as_str(), s.depends_on.len()))
            .collect();
        let mut order = Vec::with_capacity(self.stages.len());
        let mut ready: BTreeSet<&str> = waiting
            .iter()
            .filter(|(_, n)| **n == 0)
            .map(|(s, _)| *s)
            .collect();
        while let Some(name) = ready.pop_first() {
            order.push(name);
            for stage in &self.stages {
                let edges = stage
                    .depends_on
                    .iter()
                    .filter(|d| d.as_str() == name)
                    .count();
                if edges > 0
                    && let Some(n) = waiting.get_mut(stage.name.as_str())
                {
                    *n -= edges;
                    if *n == 0 {
                        ready.insert(stage.name.as_str());
                    }
                }
            }
        }
        order
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_orders_its_stages() {
        let spec = JobSpec::chain(&["ingest", "ground", "export"]);
        assert!(spec.validate().is_ok());
        assert_eq!(spec.topological_order(), ["ingest", "ground", "export"]);
        assert_eq!(spec.stages[2].depends_on, ["ground"]);
    }

    #[test]
    fn a_diamond_is_valid() {
        let spec = JobSpec::new(vec![
            StageSpec::new("a"),
            StageSpec::new("b").after("a"),
            StageSpec::new("c").after("a"),
            StageSpec::new("d").after("b").after("c"),
        ]);
        assert!(spec.validate().is_ok());
        assert_eq!(spec.topological_order(), ["a", "b", "c", "d"]);
    }

    #[test]
    fn bad_graphs_are_refused_with_a_reason() {
        let cases = [
            (JobSpec::new(vec![]), "at least one stage"),
            (
                JobSpec::new(vec![StageSpec::new("a"), StageSpec::new("a")]),
                "twice",
            ),
            (
                JobSpec::new(vec![StageSpec::new("a").after("x")]),
                "unknown stage x",
            ),
            (
                JobSpec::new(vec![
                    StageSpec::new("a").after("b"),
                    StageSpec::new("b").after("a"),
                ]),
                "cycle",
            ),
            (JobSpec::new(vec![StageSpec::new("a").after("a")]), "cycle"),
            (
                JobSpec::new(vec![StageSpec::new("a").with_max_attempts(0)]),
                "max_attempts",
            ),
            (JobSpec::new(vec![StageSpec::new("")]), "1 to 100 bytes"),
        ];
        for (spec, reason) in cases {
            let err = spec.validate().expect_err("invalid spec");
            assert!(
                err.to_string().contains(reason),
                "{err} should mention {reason}"
            );
        }
    }
}
