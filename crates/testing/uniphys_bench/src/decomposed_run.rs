//! `articulation-bench --decompose`: a URDF asset merged into one mesh at rest (no parts, names
//! or joints), decomposed by the built-in stage as `uniphys run --decompose` does, run, and its
//! parts paired with the true ones by shared surface, as `uniphys eval --match-parts overlap`
//! pairs them.

use std::path::Path;

use uniphys_decompose::output::obj_text;
use uniphys_decompose::{BuiltinSegmenter, DecomposeOptions, GeometricGenerator, decompose_asset};
use uniphys_eval::{
    AnnotatedAsset, PartOverlap, annotated_from_mesh_asset, load_prediction_with_surfaces,
    load_urdf_asset, match_parts_by_overlap, mesh_asset_part_surfaces, renamed_by_overlap,
};
use uniphys_geometry::TriMesh;
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::UpAxis;

/// The prediction (its parts renamed to the true parts they match), the ground truth, and the
/// part matches; the message of the first step that failed otherwise. A mesh the stage cuts
/// into more than `max_parts` parts is left out with that reason: grounding takes minutes per
/// few dozen parts.
pub(crate) fn run_decomposed(
    urdf: &Path,
    ingest: &IngestOptions,
    work: &Path,
    max_parts: usize,
) -> Result<(AnnotatedAsset, AnnotatedAsset, Vec<PartOverlap>), String> {
    let text = |e: &dyn std::fmt::Display| e.to_string();
    let truth = load_urdf_asset(urdf, ingest).map_err(|e| text(&e))?;
    let merged = truth.merged();
    let bare = TriMesh {
        positions: merged.positions,
        triangles: merged.triangles,
        ..TriMesh::default()
    };
    std::fs::create_dir_all(work).map_err(|e| text(&e))?;
    let input = work.join("merged.obj");
    std::fs::write(&input, obj_text(&bare)).map_err(|e| text(&e))?;
    // The merged mesh is in the ground truth's frame (Z up, its unit): read as written. The
    // dynamic check only reports (it changes no joint), and on a mesh cut into many small
    // fragments it is most of the run: off.
    let mut options = RunOptions {
        ingest: IngestOptions {
            up_axis: Some(UpAxis::Z),
            max_triangles: ingest.max_triangles,
            ..IngestOptions::default()
        },
        ..RunOptions::default()
    };
    options.verify.dynamics = None;
    // Decomposed here, on the mesh as the run reads it, to count the parts; the run applies
    // this face-to-part map instead of decomposing again.
    let read = load_asset(&input, &options.ingest).map_err(|e| text(&e))?;
    let (_, decomposition) = decompose_asset(
        &read.asset,
        &BuiltinSegmenter::default(),
        &GeometricGenerator::default(),
        &DecomposeOptions::default(),
    )
    .map_err(|e| text(&e))?;
    if decomposition.part_count > max_parts {
        return Err(format!(
            "decomposed into {} parts, more than --max-parts {max_parts}",
            decomposition.part_count
        ));
    }
    options.face_parts = Some(decomposition.face_part);
    let output = run(&input, &options, &NoProgress).map_err(|e| text(&e))?;
    let out = work.join("out");
    for artifact in &output.artifacts {
        if artifact.path == "record.json" || artifact.path.starts_with("parts/") {
            let path = out.join(&artifact.path);
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).map_err(|e| text(&e))?;
            }
            std::fs::write(&path, &artifact.bytes).map_err(|e| text(&e))?;
        }
    }
    let (pred, pred_surfaces) = load_prediction_with_surfaces(&out).map_err(|e| text(&e))?;
    let gt = annotated_from_mesh_asset(&truth, &urdf.display().to_string());
    let matches = match_parts_by_overlap(
        &pred,
        &pred_surfaces,
        &gt,
        &mesh_asset_part_surfaces(&truth),
    )
    .map_err(|e| text(&e))?;
    Ok((renamed_by_overlap(&pred, &matches), gt, matches))
}
