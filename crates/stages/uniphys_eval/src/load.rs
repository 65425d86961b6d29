//! Which loader reads a path: predictions are our `record.json` files; ground truth is a
//! `record.json`, a UniPhys-40K entity directory, or a URDF (file or PartNet-Mobility folder).

use std::path::Path;

use uniphys_mesh_io::IngestOptions;

use crate::annotated::AnnotatedAsset;
use crate::load_dataset::{is_dataset_entity, load_dataset_ground_truth};
use crate::load_mesh_asset::load_urdf_ground_truth;
use crate::load_record::{annotated_from_record, read_record, record_path};
use crate::{EvalError, EvalResult};

/// What a ground-truth path holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroundTruthKind {
    /// A `record.json` (or a `uniphys run` output directory).
    Record,
    /// A UniPhys-40K entity directory.
    Dataset,
    /// A `.urdf` file or a folder holding one.
    Urdf,
}

/// The kind of ground truth at `path`, by its shape: a directory with `record.json`, then one
/// with `annotations/part_*.json`, then one with a `.urdf`; a `.json` or `.urdf` file.
pub fn ground_truth_kind(path: &Path) -> EvalResult<GroundTruthKind> {
    let unrecognised = || EvalError::UnrecognisedInput {
        path: path.to_path_buf(),
        expected: "a ground truth: a URDF file or folder (PartNet-Mobility style), a record.json or an output directory holding one, or a UniPhys-40K entity directory",
    };
    if path.is_dir() {
        if record_path(path).is_some() {
            Ok(GroundTruthKind::Record)
        } else if is_dataset_entity(path) {
            Ok(GroundTruthKind::Dataset)
        } else if uniphys_mesh_io::detect_format(path).is_ok() {
            Ok(GroundTruthKind::Urdf)
        } else {
            Err(unrecognised())
        }
    } else if !path.exists() {
        Err(EvalError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file or directory"),
        })
    } else {
        match path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
        {
            Some(e) if e == "json" => Ok(GroundTruthKind::Record),
            Some(e) if e == "urdf" => Ok(GroundTruthKind::Urdf),
            _ => Err(unrecognised()),
        }
    }
}

/// Loads a prediction: a `record.json` or a `uniphys run` output directory.
pub fn load_prediction(path: &Path) -> EvalResult<AnnotatedAsset> {
    if !path.exists() {
        return Err(EvalError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file or directory"),
        });
    }
    let record = read_record(path)?;
    Ok(annotated_from_record(&record, &path.display().to_string()))
}

/// Loads a ground truth of any [`GroundTruthKind`]; a URDF is ingested with `options` (units, up
/// axis and rotation of the run being evaluated) and rested on the ground.
pub fn load_ground_truth(path: &Path, options: &IngestOptions) -> EvalResult<AnnotatedAsset> {
    match ground_truth_kind(path)? {
        GroundTruthKind::Record => {
            let record = read_record(path)?;
            Ok(annotated_from_record(&record, &path.display().to_string()))
        }
        GroundTruthKind::Dataset => load_dataset_ground_truth(path),
        GroundTruthKind::Urdf => load_urdf_ground_truth(path, options),
    }
}
