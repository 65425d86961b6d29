//! The `infer`, `prepare`, `colliders` and `ground` stages of a run: a UniPhysGen server's answers
//! when one is configured, each part's solid and walls, its convex hulls, then its material,
//! properties and mass and the articulation (the built-in grounder, then the UniPhysGen server's
//! answers and an LVLM's when configured). What grounding decided, with the colliders, is a
//! [`GroundedAsset`], which the queue stores so that verification and export never ask the models
//! again nor decompose the parts into hulls again.

use std::sync::atomic::{AtomicUsize, Ordering};

use uniphys_geometry::{
    DVec3, MassProperties, MeshAsset, TriMesh, VolumeMethod, WallSamples, convex_decompositions,
    materials_by_coverage, parallel_map, solid_mass_properties,
};
use uniphys_ground::{
    MAX_WALL_FACTOR, ObjectKind, PartInput, PartMassInput, RigidMass, articulate, ground_part,
    object_properties, part_mass_model, walls_matter,
};
use uniphys_types::{
    AssetRecord, Estimate, GroundedAsset, Hull, PartId, PartMass, PartRecord, Provenance,
    SCHEMA_VERSION,
};
use uniphys_uniphysgen::ModelAnswers;

use crate::input::Input;
use crate::learned::{apply_answers, infer_answers};
use crate::lvlm::ground_lvlm;
use crate::mass_calibration::calibrate_walls;
use crate::run::{Clock, RunOptions};
use crate::{PipelineError, PipelineResult, Stage};

/// Samples of a part's surface for its wall model.
const WALL_SAMPLES: usize = 4000;
/// Seed of those samples.
const WALL_SEED: u64 = 0x5EED;

/// Prepared geometry of one part.
pub(crate) struct Prepared {
    /// The solid the part's surface encloses (its voxels when it is open).
    pub(crate) mass: MassProperties,
    pub(crate) method: VolumeMethod,
    /// The part's surface sampled with the gaps between its walls (`None` when it has no area or
    /// its walls cannot matter, see `walls_matter`).
    pub(crate) walls: Option<WallSamples>,
}

/// The `prepare` stage: every part's solid mass properties and, where they matter, its walls.
pub(crate) fn prepare(
    input: &Input,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<Vec<Prepared>> {
    let progress = clock.progress;
    let interior_fill = input.kind.as_ref().map(|k| k.prior.interior_fill);
    clock.stage(Stage::Prepare, || {
        let total = input.asset.parts.len();
        let done = AtomicUsize::new(0);
        let prepared: Vec<PipelineResult<Prepared>> = parallel_map(&input.asset.parts, |part| {
            let result = solid_mass_properties(&part.mesh, options.voxel_resolution)
                .map(|(mass, method)| Prepared {
                    mass,
                    method,
                    walls: walls_matter(method, interior_fill)
                        .then(|| WallSamples::of_mesh(&part.mesh, WALL_SAMPLES, WALL_SEED))
                        .flatten(),
                })
                .map_err(|source| PipelineError::Geometry {
                    part: part.name.clone(),
                    source,
                });
            let finished = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress.stage_advanced(Stage::Prepare, finished, total);
            result
        });
        let prepared: Vec<Prepared> = prepared.into_iter().collect::<PipelineResult<_>>()?;
        let closed = prepared
            .iter()
            .filter(|p| p.method == VolumeMethod::ClosedMesh)
            .count();
        Ok((
            prepared,
            format!("{closed} of {total} parts closed (exact mass properties), others voxelised"),
        ))
    })
}

/// The `colliders` stage: every part's convex hulls.
pub(crate) fn colliders(
    input: &Input,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<Vec<Vec<TriMesh>>> {
    let progress = clock.progress;
    let asset = &input.asset;
    clock.stage(Stage::Colliders, || {
        let meshes: Vec<&TriMesh> = asset.parts.iter().map(|p| &p.mesh).collect();
        let advanced = |done, total| progress.stage_advanced(Stage::Colliders, done, total);
        // One call for all parts: a shape repeated across parts (an oven's knobs) is decomposed
        // once.
        let hulls =
            convex_decompositions(&meshes, &options.convex, &advanced).map_err(|source| {
                PipelineError::Geometry {
                    part: "every part".to_owned(),
                    source,
                }
            })?;
        let hulls: Vec<Vec<TriMesh>> = hulls
            .into_iter()
            .zip(&asset.parts)
            .map(|(hulls, part)| {
                hulls.map_err(|source| PipelineError::Geometry {
                    part: part.name.clone(),
                    source,
                })
            })
            .collect::<PipelineResult<_>>()?;
        let count: usize = hulls.iter().map(Vec::len).sum();
        Ok((
            hulls,
            format!("{count} convex hulls for {} parts", asset.parts.len()),
        ))
    })
}

/// The `ground` stage: the built-in grounder, then the UniPhysGen server's `answers` (the
/// `infer` stage's) and the LVLM's answers when the options configure one.
pub(crate) fn ground(
    input: &Input,
    prepared: &[Prepared],
    colliders: &[Vec<TriMesh>],
    answers: Option<&ModelAnswers>,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<GroundedAsset> {
    clock.stage(Stage::Ground, || {
        let asset = &input.asset;
        let (mut record, mut notes) = ground_builtin(
            &input.name,
            input.source.clone(),
            input.kind.as_ref(),
            asset,
            prepared,
            colliders,
        )?;
        if let Some(answers) = answers {
            notes.extend(apply_answers(
                asset,
                prepared,
                colliders,
                &mut record,
                answers,
            )?);
        }
        let mut accounting = None;
        if let Some(lvlm) = &options.lvlm {
            let lvlm = ground_lvlm(asset, prepared, colliders, &mut record, lvlm)?;
            notes.extend(lvlm.notes);
            accounting = Some(lvlm.accounting);
        }
        let movable = record.joints.iter().filter(|j| j.kind.is_movable()).count();
        let mut summary = format!(
            "{} movable joints, object mass {:.3} kg ({})",
            movable, record.object.mass_kg.value, record.object.category.value
        );
        if let Some(accounting) = accounting {
            summary = format!("{summary}; {accounting}");
        }
        let hulls = colliders
            .iter()
            .map(|part| part.iter().map(hull_of).collect())
            .collect();
        Ok((GroundedAsset::new(record, notes, hulls), summary))
    })
}

/// The `infer` stage: the UniPhysGen server's answers about `input`'s parts and object: the
/// stored ones (`RunOptions::inferred`, checked here against the parts), else [`ask_model`]'s.
pub(crate) fn infer(
    input: &Input,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<Option<ModelAnswers>> {
    match &options.inferred {
        Some(stored) => Ok(Some(stored.clone().checked(input.asset.parts.len())?)),
        None => ask_model(input, options, clock),
    }
}

/// The `infer` stage asking the server the options configure, if any (stored answers are not
/// looked at).
pub(crate) fn ask_model(
    input: &Input,
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<Option<ModelAnswers>> {
    let Some(learned) = &options.learned else {
        return Ok(None);
    };
    clock.stage(Stage::Infer, || {
        let answers = infer_answers(&input.asset, &input.name, learned)?;
        let summary = format!(
            "the UniPhysGen model {:?} answered for {} parts",
            answers.object_model,
            answers.physics.parts.len()
        );
        Ok((Some(answers), summary))
    })
}

/// A collider as stored.
fn hull_of(mesh: &TriMesh) -> Hull {
    Hull {
        positions_m: mesh.positions.iter().map(|p| p.to_array()).collect(),
        triangles: mesh.triangles.clone(),
    }
}

/// The colliders a stored grounding holds, as meshes.
pub(crate) fn stored_colliders(grounded: &GroundedAsset) -> PipelineResult<Vec<Vec<TriMesh>>> {
    grounded
        .colliders
        .iter()
        .zip(&grounded.record.parts)
        .map(|(hulls, part)| {
            hulls
                .iter()
                .map(|h| {
                    let positions = h
                        .positions_m
                        .iter()
                        .map(|p| DVec3::from_array(*p))
                        .collect();
                    TriMesh::new(positions, h.triangles.clone()).map_err(|e| {
                        PipelineError::StoredGrounding(format!(
                            "a collider of part {:?}: {e}",
                            part.name
                        ))
                    })
                })
                .collect()
        })
        .collect()
}

/// A grounding stored by an earlier run of the `ground` stage, checked against the parts it is
/// applied to: the same parts, by count and name.
pub(crate) fn stored_grounding(
    grounded: &GroundedAsset,
    asset: &MeshAsset,
) -> PipelineResult<GroundedAsset> {
    let grounded = grounded.clone().checked()?;
    let stored: Vec<&str> = grounded
        .record
        .parts
        .iter()
        .map(|p| p.name.as_str())
        .collect();
    let read: Vec<&str> = asset.parts.iter().map(|p| p.name.as_str()).collect();
    if stored != read {
        return Err(PipelineError::StoredGrounding(format!(
            "it names the parts {stored:?}, the input has {read:?}"
        )));
    }
    Ok(grounded)
}

fn ground_builtin(
    name: &str,
    source: uniphys_types::SourceInfo,
    kind: Option<&ObjectKind>,
    asset: &MeshAsset,
    prepared: &[Prepared],
    colliders: &[Vec<TriMesh>],
) -> PipelineResult<(AssetRecord, Vec<String>)> {
    let mut parts = Vec::with_capacity(asset.parts.len());
    let mut rigid = Vec::with_capacity(asset.parts.len());
    let mut shells = 0;
    for (i, (part, prep)) in asset.parts.iter().zip(prepared).enumerate() {
        let material_names: Vec<&str> = materials_by_coverage(&part.mesh)
            .into_iter()
            .filter_map(|m| asset.materials.get(m as usize).map(|mat| mat.name.as_str()))
            .collect();
        let properties = ground_part(&material_names, &part.name, kind);
        let density = properties.density_kg_per_m3.value;
        let bounds = part.mesh.bounds();
        let model = part_mass_model(&PartMassInput {
            solid: &prep.mass,
            solid_method: prep.method,
            walls: prep.walls.as_ref(),
            hulls: &colliders[i],
            material: properties.material.value.category,
            subtype: &properties.material.value.subtype,
            largest_side_m: bounds.extents().max_element(),
            interior_fill: kind.map(|k| k.prior.interior_fill),
        });
        let walls = model.method.starts_with("shell_");
        shells += usize::from(walls);
        let mass_kg = model.mass.mass_kg(density);
        let inertia = model.mass.inertia_kg_m2(density);
        rigid.push(RigidMass {
            mass_kg,
            com: model.mass.com,
            inertia_about_com_kg_m2: inertia,
        });
        parts.push(PartRecord {
            id: PartId(u32::try_from(i).unwrap_or(u32::MAX)),
            name: part.name.clone(),
            triangle_count: part.mesh.triangle_count(),
            bounds_in_object_m: [bounds.min.to_array(), bounds.max.to_array()],
            properties,
            mass: PartMass {
                volume_m3: model.mass.volume_m3,
                volume_method: model.method,
                mass_kg: Estimate::new(
                    mass_kg,
                    Provenance::rule(if walls {
                        "density_times_surface_area_times_wall_thickness"
                    } else {
                        "density_times_volume"
                    }),
                ),
                com_in_object_m: model.mass.com.to_array(),
                inertia_about_com_kg_m2: inertia.transpose().to_cols_array_2d(),
            },
        });
    }
    let calibration = kind.map(|k| calibrate_walls(&mut parts, &mut rigid, k.prior.mass_kg));
    let inputs: Vec<PartInput<'_>> = asset
        .parts
        .iter()
        .zip(prepared)
        .zip(&rigid)
        .zip(colliders)
        .map(|(((part, prep), mass), hulls)| PartInput {
            name: &part.name,
            mesh: &part.mesh,
            volume_m3: prep.mass.volume_m3,
            mass: *mass,
            colliders: hulls,
        })
        .collect();
    let mut articulation = articulate(&inputs, &asset.joints)?;
    let masses: Vec<f64> = rigid.iter().map(|r| r.mass_kg).collect();
    let object = object_properties(name, kind, asset.bounds().extents().to_array(), &masses);
    articulation.notes.push(format!(
        "mass: {shells} of {} parts are walls along their surface (less material than the solid they enclose), the others solid",
        asset.parts.len()
    ));
    if let Some(factor) = calibration.filter(|f| (f - 1.0).abs() > 1e-9) {
        articulation.notes.push(format!(
            "mass: the walls' mass x {factor:.2}, the square root of the kind's typical {:.3} kg over the parts' own estimate (walls alone then weigh the geometric mean of the two; at most {MAX_WALL_FACTOR}x either way)",
            kind.map_or(f64::NAN, |k| k.prior.mass_kg)
        ));
    }
    let record = AssetRecord {
        schema_version: SCHEMA_VERSION,
        name: name.to_owned(),
        source,
        object,
        parts,
        root: articulation.root,
        joints: articulation.joints,
    };
    record.validate()?;
    Ok((record, articulation.notes))
}
