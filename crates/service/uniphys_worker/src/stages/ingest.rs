//! `ingest`: reads the submitted file with the mesh reader, so a broken input fails fast with a
//! permanent, readable error before any heavy stage runs; writes a summary of what was read and
//! what was read itself (`asset.bin`, an [`IngestedAsset`]), which every later stage reads
//! instead of parsing the source again.

use serde_json::Value;
use uniphys_mesh_io::{IngestOptions, IngestedAsset, load_asset};
use uniphys_pipeline::asset_name;
use uniphys_types::{IngestSummary, ServiceStage};

use crate::input_error::unreadable;
use crate::outputs::{OutputWriter, summary_value};
use crate::source::SourceFile;
use crate::stage::{Stage, StageControl, StageError, StageInput};
use crate::stages::upstream::INGESTED_FILE;

/// Warnings the run's manifest carries (summary.json has all of them).
const MANIFEST_WARNINGS: usize = 5;

/// The ingest stage.
#[derive(Clone, Debug, Default)]
pub struct IngestStage {
    /// Reader options (units, up axis, limits).
    pub options: IngestOptions,
}

impl Stage for IngestStage {
    fn name(&self) -> &str {
        ServiceStage::Ingest.name()
    }

    fn version(&self) -> u32 {
        // 2: writes what it read (`asset.bin`).
        2
    }

    fn run(
        &self,
        input: &StageInput,
        out: &mut OutputWriter,
        control: &StageControl,
    ) -> Result<Value, StageError> {
        control.progress(0.1, "fetching the source");
        let source = SourceFile::fetch(input)?;
        control.check()?;
        control.progress(0.5, "reading the mesh");
        let mut loaded =
            load_asset(source.path(), &self.options).map_err(|e| unreadable(&source, &e))?;
        // Named by their place in the asset's folder, not the worker's: a retry on another
        // worker writes the same summary and the same stored asset.
        let warnings: Vec<String> = loaded
            .warnings
            .iter()
            .map(|w| source.without_local_paths(w))
            .collect();
        loaded.warnings.clone_from(&warnings);
        let summary = IngestSummary {
            file: source.file_name(),
            parts: loaded.asset.parts.len(),
            triangles: loaded.asset.triangle_count(),
            declared_joints: loaded.asset.joints.len(),
            dropped_degenerate_triangles: loaded.dropped_degenerate_triangles,
            warnings,
            warning_count: None,
        };
        control.check()?;
        control.progress(0.8, "storing what was read");
        let ingested = IngestedAsset {
            name: asset_name(source.path()),
            loaded,
        };
        let bytes = ingested
            .to_bytes()
            .map_err(|e| StageError::Permanent(format!("storing what was read: {e}")))?;
        out.put(INGESTED_FILE, bytes)?;
        out.put_json("summary.json", &summary)?;
        summary_value(&summary.for_manifest(MANIFEST_WARNINGS))
    }
}
