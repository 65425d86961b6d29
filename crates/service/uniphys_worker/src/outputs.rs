//! Writing a stage's artifacts under deterministic keys, so a re-run of the same stage on the
//! same input writes the same keys with the same bytes (exactly-once effects from at-least-once
//! execution), and collecting them into the run's output manifest.

use serde_json::{Value, json};
use sha2::{Digest, Sha256};
use uniphys_queue::{ArtifactEntry, OutputManifest};
use uniphys_storage::{ArtifactKey, ArtifactStore, PutOutcome, StorageError};

use crate::stage::{StageError, StageInput};

/// Collects the artifacts a stage run writes.
pub struct OutputWriter {
    prefix: ArtifactKey,
    artifacts: ArtifactStore,
    runtime: tokio::runtime::Handle,
    written: Vec<ArtifactEntry>,
    already_present: usize,
    created: Vec<String>,
}

/// The digest of everything a stage's output depends on: the asset's content digest, the stage
/// and its version, and the content digests of its upstream artifacts.
#[must_use]
pub fn input_digest(input: &StageInput, stage: &str, version: u32) -> String {
    let upstream: Vec<Value> = input
        .upstream
        .iter()
        .map(|(name, manifest)| {
            let files: Vec<(&str, &str)> = manifest
                .artifacts
                .iter()
                .map(|a| (a.name.as_str(), a.sha256.as_str()))
                .collect();
            json!([name, files])
        })
        .collect();
    let identity = json!({
        "content": input.asset.content_digest,
        "stage": stage,
        "version": version,
        "upstream": upstream,
    });
    hex::encode(Sha256::digest(identity.to_string().as_bytes()))
}

impl OutputWriter {
    /// A writer for `stage` (at `version`) of `input`'s asset.
    #[must_use]
    pub fn new(input: &StageInput, stage: &str, version: u32) -> Self {
        Self {
            prefix: ArtifactKey {
                asset: input.asset.id.0.to_string(),
                stage: stage.to_owned(),
                stage_version: version,
                input_digest: input_digest(input, stage, version),
            },
            artifacts: input.artifacts.clone(),
            runtime: input.runtime.clone(),
            written: Vec::new(),
            already_present: 0,
            created: Vec::new(),
        }
    }

    /// The key prefix of this run's artifacts.
    #[must_use]
    pub fn prefix(&self) -> &ArtifactKey {
        &self.prefix
    }

    /// Writes `value` as pretty-printed JSON named `name`, as [`OutputWriter::put`] does.
    pub fn put_json(
        &mut self,
        name: &str,
        value: &impl serde::Serialize,
    ) -> Result<(), StageError> {
        let bytes = serde_json::to_vec_pretty(value)
            .map_err(|e| StageError::Permanent(format!("encoding {name}: {e}")))?;
        self.put(name, bytes)
    }

    /// Writes `bytes` as `name` (create-only: the same bytes already there count as written;
    /// different bytes under the same key are a permanent error).
    pub fn put(&mut self, name: &str, bytes: Vec<u8>) -> Result<(), StageError> {
        let key = self
            .prefix
            .file(name)
            .map_err(|e| StageError::Permanent(e.to_string()))?;
        let sha256 = hex::encode(Sha256::digest(&bytes));
        let size = bytes.len() as u64;
        match self.runtime.block_on(self.artifacts.put_once(&key, bytes)) {
            Ok(PutOutcome::Created) => self.created.push(key.clone()),
            Ok(PutOutcome::AlreadyPresent) => self.already_present += 1,
            Err(e @ StorageError::Conflict { .. }) => {
                return Err(StageError::Permanent(format!(
                    "{e}: the stage is not deterministic for its input"
                )));
            }
            Err(e) => return Err(StageError::Transient(format!("writing {key}: {e}"))),
        }
        self.written.push(ArtifactEntry {
            name: name.to_owned(),
            key,
            bytes: size,
            sha256,
        });
        Ok(())
    }

    /// How many writes found their object already there (a re-run after a crash).
    #[must_use]
    pub fn already_present(&self) -> usize {
        self.already_present
    }

    /// Keys of the objects this run created (not those it found already there): what to remove
    /// when its result is dropped.
    #[must_use]
    pub fn created_keys(&self) -> Vec<String> {
        self.created.clone()
    }

    /// The manifest of what was written, with `summary`.
    #[must_use]
    pub fn into_manifest(self, summary: Value) -> OutputManifest {
        OutputManifest {
            artifacts: self.written,
            summary,
        }
    }
}

/// A stage's typed summary as its run's manifest stores it.
pub(crate) fn summary_value(
    summary: &impl serde::Serialize,
) -> Result<serde_json::Value, StageError> {
    serde_json::to_value(summary)
        .map_err(|e| StageError::Permanent(format!("the summary could not be written: {e}")))
}
