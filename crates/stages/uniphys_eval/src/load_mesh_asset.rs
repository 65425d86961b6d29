//! Ground truth from an articulated mesh asset: a PartNet-Mobility-style URDF (folder or file)
//! ingested like `uniphys run` ingests it, or a [`MeshAsset`] built in memory.

use std::path::Path;

use uniphys_geometry::MeshAsset;
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::{JointKind, PartId};

use crate::annotated::AnnotatedAsset;
use crate::load_record::annotated_joint;
use crate::{AnnotatedPart, EvalError, EvalResult};

/// Loads a URDF (a `.urdf` file or a folder holding one) with `options` (the same units, up
/// axis and rotation as the run being evaluated; its `ignore_joints` is not applied: the joints
/// are the ground truth), moves it to rest on z = 0 centred in x and y as the pipeline does, and
/// returns it as ground truth.
pub fn load_urdf_ground_truth(path: &Path, options: &IngestOptions) -> EvalResult<AnnotatedAsset> {
    let asset = load_urdf_asset(path, options)?;
    Ok(annotated_from_mesh_asset(
        &asset,
        &path.display().to_string(),
    ))
}

/// The URDF as [`load_urdf_ground_truth`] loads it, before it becomes ground truth: a mesh
/// asset with its joints, rested on the ground.
pub fn load_urdf_asset(path: &Path, options: &IngestOptions) -> EvalResult<MeshAsset> {
    let options = IngestOptions {
        ignore_joints: false,
        ..options.clone()
    };
    let mut loaded = load_asset(path, &options).map_err(|source| EvalError::Ingest {
        path: path.to_path_buf(),
        source,
    })?;
    loaded.asset.rest_on_ground();
    Ok(loaded.asset)
}

/// A [`MeshAsset`] with declared joints as ground truth, in its own frame (callers bring it into
/// the frame of the prediction, e.g. with [`MeshAsset::rest_on_ground`]). Parts carry no
/// physics and there are no object values. A movable joint's group is its child plus the
/// parts attached to the child through chains of fixed joints (and any `coupled_parts` given).
#[must_use]
pub fn annotated_from_mesh_asset(asset: &MeshAsset, origin: &str) -> AnnotatedAsset {
    let name_of = |id: PartId| {
        asset
            .parts
            .get(id.0 as usize)
            .map_or_else(|| id.to_string(), |p| p.name.clone())
    };
    let joints = asset
        .joints
        .iter()
        .map(|joint| {
            let mut joint = joint.clone();
            if joint.kind.is_movable() {
                joint
                    .coupled_parts
                    .extend(fixed_descendants(asset, joint.child));
            }
            annotated_joint(&joint, &name_of)
        })
        .collect();
    let bounds = asset.bounds();
    AnnotatedAsset {
        origin: origin.to_owned(),
        bounds_in_object: (!bounds.is_empty())
            .then(|| [bounds.min.to_array(), bounds.max.to_array()]),
        parts: asset
            .parts
            .iter()
            .map(|p| AnnotatedPart {
                name: p.name.clone(),
                physics: None,
            })
            .collect(),
        joints,
        object: None,
    }
}

/// Parts hanging off `part` through fixed joints only, at any depth.
fn fixed_descendants(asset: &MeshAsset, part: PartId) -> Vec<PartId> {
    let mut found = Vec::new();
    let mut stack = vec![part];
    while let Some(p) = stack.pop() {
        for j in &asset.joints {
            if j.parent == p && j.kind == JointKind::Fixed && !found.contains(&j.child) {
                found.push(j.child);
                stack.push(j.child);
            }
        }
    }
    found
}
