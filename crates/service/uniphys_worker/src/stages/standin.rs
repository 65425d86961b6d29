//! A fast stand-in stage for tests, crash tests and benchmarks: it hashes its input, writes one
//! small artifact whose bytes depend only on its input (so a re-run must write the same bytes)
//! and then optionally works a while, as a real stage writes files before it finishes.

use std::time::Duration;

use serde_json::{Value, json};
use sha2::{Digest, Sha256};

use crate::outputs::OutputWriter;
use crate::stage::{Stage, StageControl, StageError, StageInput};

/// A deterministic stand-in stage named `name` that works for `work` (sleeping in small steps,
/// reporting progress and honouring cancellation).
#[derive(Clone, Debug)]
pub struct StandInStage {
    name: String,
    work: Duration,
}

impl StandInStage {
    /// A stand-in called `name` that takes `work`.
    #[must_use]
    pub fn new(name: impl Into<String>, work: Duration) -> Self {
        Self {
            name: name.into(),
            work,
        }
    }
}

/// The bytes a stand-in stage writes for its input: `stage:sha256(content digest + upstream)`.
#[must_use]
pub fn standin_output(stage: &str, input: &StageInput) -> Vec<u8> {
    let mut hasher = Sha256::new();
    hasher.update(input.asset.content_digest.as_bytes());
    for (name, manifest) in &input.upstream {
        hasher.update(name.as_bytes());
        for artifact in &manifest.artifacts {
            hasher.update(artifact.sha256.as_bytes());
        }
    }
    format!("{stage}:{}\n", hex::encode(hasher.finalize())).into_bytes()
}

impl Stage for StandInStage {
    fn name(&self) -> &str {
        &self.name
    }

    fn version(&self) -> u32 {
        1
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        out.put("out.txt", standin_output(&self.name, input))?;
        let steps = 10u32;
        for step in 0..steps {
            control.check()?;
            std::thread::sleep(self.work / steps);
            control.progress(f64::from(step + 1) / f64::from(steps), "working");
        }
        Ok(json!({ "stand_in": true, "rewrites": out.already_present() }))
    }
}
