//! An exported file: a path relative to the asset's output directory and its bytes.

use serde::Serialize;

use crate::{ExportError, ExportResult};

/// One output file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Artifact {
    /// Path relative to the asset directory, `/`-separated (e.g. `meshes/part_0_visual.obj`).
    pub path: String,
    /// File contents.
    pub bytes: Vec<u8>,
}

impl Artifact {
    /// An artifact from raw bytes.
    pub fn new(path: impl Into<String>, bytes: Vec<u8>) -> Self {
        Self {
            path: path.into(),
            bytes,
        }
    }

    /// An artifact holding pretty-printed JSON.
    pub fn json(path: impl Into<String>, value: &impl Serialize) -> ExportResult<Self> {
        let path = path.into();
        let mut bytes = serde_json::to_vec_pretty(value).map_err(|e| ExportError::Json {
            path: path.clone(),
            message: e.to_string(),
        })?;
        bytes.push(b'\n');
        Ok(Self { path, bytes })
    }
}
