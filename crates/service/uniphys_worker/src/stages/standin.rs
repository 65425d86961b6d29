//! A fast stand-in stage for tests, crash tests and benchmarks: it hashes its input, writes one
//! small artifact whose bytes depend only on its input (so a re-run must write the same bytes)
//! and then optionally works a while, as a real stage writes files before it finishes. A
//! stand-in `convert` also writes the smallest dataset entity (object annotation, record, report,
//! all saying they come from a stand-in), so a batch of stand-in jobs can be exported.

use std::time::Duration;

use serde_json::{Value, json};
use sha2::{Digest, Sha256};
use uniphys_types::ServiceStage;

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

/// The stage whose files are an asset's dataset entity.
const CONVERT: &str = ServiceStage::Convert.name();

/// The files of a stand-in dataset entity, each naming the stand-in output it stands for.
fn standin_entity(output: &[u8]) -> [(&'static str, Vec<u8>); 3] {
    let digest = String::from_utf8_lossy(output).trim().to_owned();
    let json = |value: Value| value.to_string().into_bytes();
    [
        (
            "annotations/object.json",
            json(json!({ "category": "StandIn", "stand_in": digest })),
        ),
        (
            "record.json",
            json(json!({
                "object": { "category": { "value": "StandIn" } },
                "parts": [],
                "joints": [],
                "stand_in": digest,
            })),
        ),
        (
            "report.json",
            json(json!({ "passed": true, "stand_in": digest })),
        ),
    ]
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
        let output = standin_output(&self.name, input);
        out.put("out.txt", output.clone())?;
        if self.name == CONVERT {
            for (name, bytes) in standin_entity(&output) {
                out.put(name, bytes)?;
            }
        }
        let steps = 10u32;
        for step in 0..steps {
            control.check()?;
            std::thread::sleep(self.work / steps);
            control.progress(f64::from(step + 1) / f64::from(steps), "working");
        }
        Ok(json!({ "stand_in": true, "rewrites": out.already_present() }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_standin_entity_says_what_it_stands_for() {
        let files = standin_entity(b"convert:ab12\n");
        let names: Vec<&str> = files.iter().map(|(name, _)| *name).collect();
        assert_eq!(
            names,
            ["annotations/object.json", "record.json", "report.json"]
        );
        for (name, bytes) in &files {
            let value: Value = serde_json::from_slice(bytes).expect(name);
            assert_eq!(value["stand_in"], "convert:ab12", "{name}");
        }
        let object: Value = serde_json::from_slice(&files[0].1).expect("object");
        assert_eq!(object["category"], "StandIn");
        let report: Value = serde_json::from_slice(&files[2].1).expect("report");
        assert_eq!(report["passed"], true);
    }
}
