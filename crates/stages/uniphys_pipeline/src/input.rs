//! The `ingest` stage of a run: the input read (and decomposed or split into the parts of an
//! earlier decomposition), given a real size when its unit is not a length, and put to rest on
//! the ground. Every later stage works on what it returns, in metres, with z up and z = 0 under
//! the object.

use std::path::{Path, PathBuf};

use uniphys_decompose::{BuiltinSegmenter, GeometricGenerator, decompose_asset, split_asset};
use uniphys_geometry::{DMat4, DVec3, MeshAsset};
use uniphys_ground::{ObjectKind, object_kind, sanitize};
use uniphys_mesh_io::{IngestedAsset, load_asset};
use uniphys_types::SourceInfo;

use crate::real_scale::auto_scale;
use crate::run::{Clock, RunOptions};
use crate::{PipelineError, PipelineResult, Stage};

/// What a run reads: a file (or a PartNet-Mobility folder), or an asset an earlier `ingest`
/// stage read and stored ([`IngestedAsset`]), which is not parsed again.
#[derive(Clone, Copy, Debug)]
pub enum AssetSource<'a> {
    /// A file or folder the readers parse.
    File(&'a Path),
    /// What the queue's `ingest` stage read.
    Ingested(&'a IngestedAsset),
}

impl<'a> From<&'a Path> for AssetSource<'a> {
    fn from(path: &'a Path) -> Self {
        Self::File(path)
    }
}

impl<'a> From<&'a PathBuf> for AssetSource<'a> {
    fn from(path: &'a PathBuf) -> Self {
        Self::File(path)
    }
}

impl<'a> From<&'a IngestedAsset> for AssetSource<'a> {
    fn from(asset: &'a IngestedAsset) -> Self {
        Self::Ingested(asset)
    }
}

impl AssetSource<'_> {
    /// The asset's name ([`asset_name`] of a file).
    fn name(&self) -> String {
        match self {
            Self::File(path) => asset_name(path),
            Self::Ingested(asset) => asset.name.clone(),
        }
    }

    /// How messages name it: the file's path, or the stored asset's source file name.
    fn label(&self) -> String {
        match self {
            Self::File(path) => path.display().to_string(),
            Self::Ingested(asset) => asset.loaded.source.file_name.clone(),
        }
    }
}

/// An input read and put in the object frame.
pub(crate) struct Input {
    /// The asset name ([`asset_name`]).
    pub(crate) name: String,
    /// The parts, in metres, resting on z = 0 and centred in x and y.
    pub(crate) asset: MeshAsset,
    /// Where it came from (its unit includes the real-size factor).
    pub(crate) source: SourceInfo,
    /// What kind of object it is, when its names or declared category say.
    pub(crate) kind: Option<ObjectKind>,
    /// Zero-area triangles dropped by the reader.
    pub(crate) dropped: usize,
    /// The reader's warnings (missing textures, ...).
    pub(crate) warnings: Vec<String>,
    /// What was done to it and why, for the export's notes.
    pub(crate) notes: Vec<String>,
    /// Its parts were cut by a decomposition (here or stored), not authored: the still body may
    /// be several of them.
    pub(crate) decomposed: bool,
}

/// Reads the input (the run's `ingest` stage; a stored [`IngestedAsset`] is taken as it is),
/// applies the decomposition the options ask for, scales it to a real size under `--unit auto`,
/// and rests it on the ground.
pub(crate) fn read_input(
    from: AssetSource<'_>,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<Input> {
    let name = from.name();
    let (mut asset, mut source, dropped, warnings, facts, decompose_note) =
        clock.stage(Stage::Ingest, || {
            let mut loaded = match from {
                AssetSource::File(path) => load_asset(path, &options.ingest)?,
                AssetSource::Ingested(stored) => stored.loaded.clone(),
            };
            let mut summary = format!(
                "{} parts, {} triangles, {} joints declared",
                loaded.asset.parts.len(),
                loaded.asset.triangle_count(),
                loaded.asset.joints.len()
            );
            let mut decompose_note = None;
            if let Some(face_parts) = &options.face_parts {
                loaded.asset = split_asset(&loaded.asset, face_parts)?;
                summary = format!(
                    "{summary}; split into {} parts by the stored decomposition (joints dropped)",
                    loaded.asset.parts.len()
                );
                decompose_note = Some(format!(
                    "split into {} parts by the decompose stage's face-to-part map; declared joints dropped",
                    loaded.asset.parts.len()
                ));
            } else if let Some(decompose) = options
                .decompose
                .as_ref()
                .filter(|_| options.decompose_mode.applies_to(&loaded.asset))
            {
                let (parts, decomposition) = decompose_asset(
                    &loaded.asset,
                    &BuiltinSegmenter::default(),
                    &GeometricGenerator::default(),
                    decompose,
                )?;
                summary = format!(
                    "{summary}; decomposed into {} parts (joints dropped)",
                    decomposition.part_count
                );
                decompose_note = Some(format!(
                    "decomposed into {} parts by {} and {} (K matched {}, merge: {}); declared joints dropped",
                    decomposition.part_count,
                    decomposition.summary.segmenter,
                    decomposition.summary.generator,
                    decomposition.summary.matched_k,
                    decomposition.summary.merge_strategy
                ));
                loaded.asset = parts;
            }
            Ok((
                (
                    loaded.asset,
                    loaded.source,
                    loaded.dropped_degenerate_triangles,
                    loaded.warnings,
                    loaded.facts,
                    decompose_note,
                ),
                summary,
            ))
        })?;
    let decomposed = decompose_note.is_some();
    let mut notes: Vec<String> = decompose_note.into_iter().collect();
    let kind = {
        let part_names: Vec<&str> = asset.parts.iter().map(|p| p.name.as_str()).collect();
        let material_names: Vec<&str> = asset.materials.iter().map(|m| m.name.as_str()).collect();
        object_kind(
            facts.declared_category.as_deref(),
            &name,
            &part_names,
            &material_names,
        )
    };
    if options.unit_auto {
        let largest_side_m = asset.bounds().extents().max_element();
        let (factor, note) = auto_scale(facts.units, kind.as_ref(), largest_side_m);
        if factor != 1.0 {
            asset.transform(&DMat4::from_scale(DVec3::splat(factor)));
            source.metres_per_unit *= factor;
        }
        notes.extend(note);
    }
    if dropped > 0 {
        notes.push(format!(
            "{dropped} zero-area triangles were dropped at ingest"
        ));
    }
    // Joints refer to parts by index, so parts are never dropped here; ingest only produces
    // parts that have triangles.
    if let Some(empty) = asset.parts.iter().find(|p| p.mesh.triangle_count() == 0) {
        return Err(PipelineError::Empty(format!(
            "part {:?} of {} has no triangles",
            empty.name,
            from.label()
        )));
    }
    let offset = asset.rest_on_ground();
    notes.push(format!(
        "object moved by ({:.4}, {:.4}, {:.4}) m to rest on z = 0, centred in x and y",
        offset.x, offset.y, offset.z
    ));
    Ok(Input {
        name,
        asset,
        source,
        kind,
        dropped,
        warnings,
        notes,
        decomposed,
    })
}

/// The asset name: the input's file stem (or folder name), made ASCII-safe.
#[must_use]
pub fn asset_name(path: &Path) -> String {
    let stem = if path.is_dir() {
        path.file_name()
    } else {
        path.file_stem()
    };
    sanitize(
        &stem
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "asset".to_owned()),
    )
}
