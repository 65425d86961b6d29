//! Part surfaces for matching parts by overlap ([`crate::match_parts_by_overlap`]): a
//! `uniphys run` output directory's `parts/part_<id>.obj` (object frame, metres, Z up), or the
//! parts of a mesh asset; and each side of a pair loaded with them.

use std::path::Path;

use uniphys_geometry::MeshAsset;
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::UpAxis;

use crate::load::{GroundTruthKind, ground_truth_kind, load_prediction};
use crate::part_overlap::PartSurface;
use crate::{
    AnnotatedAsset, EvalError, EvalResult, annotated_from_mesh_asset, annotated_from_record,
    load_urdf_asset, read_record, record_path,
};

/// The part surfaces of a `record.json` or an output directory holding one: each part's
/// `parts/part_<id>.obj` next to it, read as written (object frame, metres, Z up).
///
/// # Errors
/// [`EvalError::Io`] when a part's file is missing, [`EvalError::PartMesh`] when one cannot be
/// read, and the record's own errors.
pub fn record_part_surfaces(path: &Path) -> EvalResult<Vec<PartSurface>> {
    let record = read_record(path)?;
    let dir = record_path(path)
        .as_deref()
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let as_written = IngestOptions {
        up_axis: Some(UpAxis::Z),
        ..IngestOptions::default()
    };
    record
        .parts
        .iter()
        .map(|part| {
            let file = dir.join("parts").join(format!("{}.obj", part.id));
            if !file.is_file() {
                return Err(EvalError::Io {
                    path: file,
                    source: std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        "matching parts by overlap reads each part's mesh from the run's output directory (parts/part_<id>.obj); give the directory `uniphys run` wrote",
                    ),
                });
            }
            let loaded = load_asset(&file, &as_written).map_err(|source| EvalError::PartMesh {
                path: file.clone(),
                source,
            })?;
            Ok((part.name.clone(), loaded.asset.merged()))
        })
        .collect()
}

/// Every part of `asset` with its mesh, in the asset's frame.
#[must_use]
pub fn mesh_asset_part_surfaces(asset: &MeshAsset) -> Vec<PartSurface> {
    asset
        .parts
        .iter()
        .map(|p| (p.name.clone(), p.mesh.clone()))
        .collect()
}

/// A prediction (a `record.json` or an output directory) with its part surfaces.
///
/// # Errors
/// As [`load_prediction`] and [`record_part_surfaces`].
pub fn load_prediction_with_surfaces(
    path: &Path,
) -> EvalResult<(AnnotatedAsset, Vec<PartSurface>)> {
    Ok((load_prediction(path)?, record_part_surfaces(path)?))
}

/// A ground truth with its part surfaces: a URDF ingested with `options` and rested as
/// [`crate::load_urdf_ground_truth`] does, or a record with its output directory's part meshes.
///
/// # Errors
/// [`EvalError::Mismatch`] for a UniPhys-40K entity (its parts are matched by name); load errors.
pub fn load_ground_truth_with_surfaces(
    path: &Path,
    options: &IngestOptions,
) -> EvalResult<(AnnotatedAsset, Vec<PartSurface>)> {
    match ground_truth_kind(path)? {
        GroundTruthKind::Record => {
            let record = read_record(path)?;
            Ok((
                annotated_from_record(&record, &path.display().to_string()),
                record_part_surfaces(path)?,
            ))
        }
        GroundTruthKind::Urdf => {
            let asset = load_urdf_asset(path, options)?;
            Ok((
                annotated_from_mesh_asset(&asset, &path.display().to_string()),
                mesh_asset_part_surfaces(&asset),
            ))
        }
        GroundTruthKind::Dataset => Err(EvalError::Mismatch(format!(
            "{}: a UniPhys-40K entity's parts are matched by name; matching by overlap needs a URDF or a run's output directory as ground truth",
            path.display()
        ))),
    }
}
