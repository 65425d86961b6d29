//! Simulation-ready export of an annotated asset, as in-memory artifacts (the caller stores them):
//!
//! | path | what |
//! |---|---|
//! | `model.urdf` | URDF for PyBullet, MuJoCo's importer, Isaac Sim, SAPIEN |
//! | `model.srdf` | pairs of links whose contacts are off (jointed, or touching at rest), for loaders that read the URDF (SAPIEN) |
//! | `model.xml` | MJCF for MuJoCo |
//! | `model.usda` | USD stage with UsdPhysics for Isaac Sim and Isaac Lab (visuals in the link's colour, textured faces bound to a preview surface) |
//! | `meshes/part_<id>_visual.obj` | visual mesh of each link, in the link frame; a part drawn with textures is split by material: `part_<id>_visual_m<k>.obj` with UVs and an MTL, its image as `texture_<t>.png` |
//! | `meshes/part_<id>_collision_<k>.obj` | convex collision hulls, in the link frame |
//! | `parts/part_<id>.obj`, `.mtl`, `texture_<t>.png` | part meshes in the object frame with UVs, materials and textures (UniPhys-40K layout) |
//! | `annotations/object.json`, `annotations/part_<id>.json`, `meta_data.json` | UniPhys-40K record |
//! | `record.json` | the full [`AssetRecord`] with provenance, SI units |
//! | `report.json` | provenance of every value, checks, notes |
//!
//! Every link frame has the object's axes; its origin is the object origin for the root, the joint
//! pivot for a jointed part and the centre of mass for a part fixed to another.

mod artifact;
mod checks;
mod error;
mod mjcf;
mod model;
mod obj_writer;
mod part_files;
mod record;
mod reexport;
mod report;
mod srdf;
mod urdf;
mod usd;
mod visuals;
mod xml;

pub use artifact::Artifact;
pub use error::{ExportError, ExportResult};
pub use record::RECORD_TYPE_NAME;
pub use reexport::Exported;

use uniphys_geometry::{SurfaceMaterial, Texture, TriMesh};
use uniphys_types::{AssetRecord, CheckOutcome, PartId, VerificationReport};

/// Directory of the link meshes, relative to the model files.
pub const MESH_DIR: &str = "meshes";

/// Everything the export needs.
#[derive(Debug, Clone, Copy)]
pub struct ExportInput<'a> {
    /// The annotated asset.
    pub record: &'a AssetRecord,
    /// Visual mesh of each part (object frame), in the order of `record.parts`.
    pub part_meshes: &'a [TriMesh],
    /// Convex collision hulls of each part (object frame), in the order of `record.parts`.
    pub colliders: &'a [Vec<TriMesh>],
    /// Display colour of each part, linear RGBA.
    pub part_colors: &'a [[f32; 4]],
    /// Materials the part meshes' face material indices refer to.
    pub materials: &'a [SurfaceMaterial],
    /// Textures the materials refer to.
    pub textures: &'a [Texture],
    /// Pairs of parts that touch at rest; their contacts are off (MJCF excludes, SRDF, USD filtered
    /// pairs), as jointed pairs' are.
    pub touching_pairs: &'a [(PartId, PartId)],
    /// Checks from earlier stages, included in `report.json`.
    pub report: &'a VerificationReport,
    /// Notes from earlier stages (what was assumed or completed).
    pub notes: &'a [String],
}

/// What the export produced: the files and the checks it ran.
#[derive(Debug, Clone)]
pub struct ExportOutput {
    /// Files, sorted by path.
    pub artifacts: Vec<Artifact>,
    /// The report written to `report.json` (the sections given plus `export`).
    pub report: VerificationReport,
}

/// Exports an annotated asset.
pub fn export(input: &ExportInput<'_>) -> ExportResult<ExportOutput> {
    let model = model::Model::build(input)?;
    let record = input.record;
    let mut artifacts = vec![
        Artifact::new("model.urdf", urdf::write_urdf(&model).into_bytes()),
        Artifact::new("model.srdf", srdf::write_srdf(&model).into_bytes()),
        Artifact::new("model.xml", mjcf::write_mjcf(&model).into_bytes()),
        Artifact::new(
            "model.usda",
            usd::write_usda(&model, input.part_meshes, input.colliders).into_bytes(),
        ),
    ];
    for (i, link) in model.links.iter().enumerate() {
        for visual in &link.visuals {
            let (obj, mtl) = visuals::visual_files(&input.part_meshes[i], visual, link.anchor);
            artifacts.push(Artifact::new(
                format!("{MESH_DIR}/{}.obj", visual.stem),
                obj,
            ));
            if let Some(mtl) = mtl {
                artifacts.push(Artifact::new(
                    format!("{MESH_DIR}/{}.mtl", visual.stem),
                    mtl,
                ));
            }
        }
        for (hull, stem) in input.colliders[i].iter().zip(&link.collision_stems) {
            artifacts.push(Artifact::new(
                format!("{MESH_DIR}/{stem}.obj"),
                obj_writer::write_obj(hull, link.anchor),
            ));
        }
        artifacts.extend(part_files::part_files(
            link.id,
            &input.part_meshes[i],
            input.materials,
            link.rgba,
        ));
    }
    let textures = part_files::texture_files(input.part_meshes, input.materials, input.textures)?;
    // The link meshes' textures beside them, for the simulator models.
    let linked: std::collections::BTreeSet<usize> = model
        .links
        .iter()
        .flat_map(|l| l.visuals.iter().filter_map(|v| v.texture))
        .collect();
    for (index, texture) in &textures {
        if linked.contains(index) {
            artifacts.push(Artifact::new(
                format!("{MESH_DIR}/{}", visuals::texture_file(*index)),
                texture.bytes.clone(),
            ));
        }
    }
    artifacts.extend(textures.into_iter().map(|(_, a)| a));
    let mut report = input.report.clone();
    // A part passes when no check about it failed in the sections run so far (intrinsic
    // verification among them).
    let part_passed = |id: PartId| {
        let subject = id.to_string();
        report
            .sections
            .iter()
            .flat_map(|s| s.checks.iter())
            .filter(|c| c.subject == subject)
            .all(|c| c.outcome != CheckOutcome::Fail)
    };
    artifacts.extend(record::record_artifacts(record, &part_passed)?);
    report
        .sections
        .push(checks::export_checks(record, input.colliders));
    artifacts.push(Artifact::json("record.json", record)?);
    artifacts.push(report::report_artifact(
        record,
        &report,
        input.notes,
        &report::contact_excludes(&model),
    )?);
    artifacts.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(ExportOutput { artifacts, report })
}
