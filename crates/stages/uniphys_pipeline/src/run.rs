//! `run`: the whole pipeline on one asset, in process, with the built-in grounder.
//!
//! Stages: ingest, prepare (frame, mass properties), colliders (convex decomposition), ground
//! (materials, properties, articulation chosen by sweeps), verify (intrinsic levels 0-4,
//! articulation sweeps with correction), export.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use uniphys_decompose::{
    BuiltinSegmenter, DecomposeMode, DecomposeOptions, GeometricGenerator, decompose_asset,
    split_asset,
};
use uniphys_export::{Artifact, ExportInput, export};
use uniphys_geometry::{
    ConvexParams, DMat4, DVec3, DistanceProbe, MassProperties, MeshAsset, TriMesh, VolumeMethod,
    WallSamples, convex_decompositions, display_rgba, materials_by_coverage, parallel_map,
    solid_mass_properties,
};
use uniphys_ground::{
    MAX_WALL_FACTOR, ObjectKind, PartInput, PartMassInput, RigidMass, articulate, ground_part,
    object_kind, object_properties, part_mass_model, sanitize, walls_matter,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::{
    AssetRecord, CheckOutcome, CheckResult, Estimate, PartId, PartMass, PartRecord, Provenance,
    ReportSection, SCHEMA_VERSION, VerificationReport,
};

use crate::cavities::carve_cavities;
use crate::learned::{LearnedOptions, ground_learned};
use crate::lvlm::{LvlmOptions, ground_lvlm};
use crate::mass_calibration::calibrate_walls;
use crate::preview::{PREVIEW_PATH, preview_png};
use crate::real_scale::auto_scale;
use crate::verify::{VerifyOptions, verify};
use crate::{PipelineError, PipelineResult, Progress, Stage};

/// Options of an in-process run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// How to read the input.
    pub ingest: IngestOptions,
    /// Voxels along the longest side of a part for the volume of open meshes (reference: 128).
    pub voxel_resolution: usize,
    /// Convex decomposition parameters for the colliders.
    pub convex: ConvexParams,
    /// Parts closer than this fraction of the object diagonal count as touching (MJCF excludes).
    pub touching_fraction: f64,
    /// Ground with a UniPhysGen model server instead of the built-in grounder's estimates.
    pub learned: Option<LearnedOptions>,
    /// Ground with an LVLM (properties, motion graph, joints chosen among candidates) after the
    /// built-in grounder; its values replace the estimates.
    pub lvlm: Option<LvlmOptions>,
    /// Verification parameters.
    pub verify: VerifyOptions,
    /// Decompose the input into parts right after ingest (built-in segmenter and generator);
    /// the decomposed parts replace the input's parts and its declared joints are dropped (they
    /// name the old parts). `None` (default) keeps the input's parts and joints.
    pub decompose: Option<DecomposeOptions>,
    /// Which inputs `decompose` applies to (`Always`: every input; `Auto`: one-piece or
    /// fragmented inputs without joints).
    pub decompose_mode: DecomposeMode,
    /// A face-to-part map of the input's merged mesh computed earlier (the queue's `decompose`
    /// stage): applied right after ingest instead of decomposing again.
    pub face_parts: Option<Vec<u32>>,
    /// `--unit auto`: an input whose coordinates are not a length (a PartNet-Mobility folder)
    /// is scaled to the typical size of its kind, and one whose unit makes it implausible for
    /// its kind is read in the common unit that fits (see `real_scale.rs`); off when the user
    /// gave the unit (`ingest.metres_per_unit` is then used as is).
    pub unit_auto: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            ingest: IngestOptions::default(),
            voxel_resolution: 128,
            convex: ConvexParams::default(),
            touching_fraction: 0.005,
            learned: None,
            lvlm: None,
            verify: VerifyOptions::default(),
            decompose: None,
            decompose_mode: DecomposeMode::Always,
            face_parts: None,
            unit_auto: true,
        }
    }
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// The annotated asset.
    pub record: AssetRecord,
    /// Exported files, sorted by path.
    pub artifacts: Vec<Artifact>,
    /// All checks that ran.
    pub report: VerificationReport,
    /// Wall time of each stage, in run order.
    pub timings: Vec<(Stage, Duration)>,
}

struct Clock<'a> {
    progress: &'a dyn Progress,
    timings: Vec<(Stage, Duration)>,
}

impl Clock<'_> {
    fn stage<T>(
        &mut self,
        stage: Stage,
        f: impl FnOnce() -> PipelineResult<(T, String)>,
    ) -> PipelineResult<T> {
        self.progress.stage_started(stage);
        let start = Instant::now();
        let (value, summary) = f()?;
        let elapsed = start.elapsed();
        self.timings.push((stage, elapsed));
        self.progress.stage_finished(stage, elapsed, &summary);
        Ok(value)
    }
}

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

/// Runs ingest, prepare, ground, colliders and export on the asset at `path`.
pub fn run(
    path: &Path,
    options: &RunOptions,
    progress: &dyn Progress,
) -> PipelineResult<RunOutput> {
    let mut clock = Clock {
        progress,
        timings: Vec::new(),
    };
    let name = asset_name(path);

    let (mut asset, mut source, dropped, ingest_warnings, facts, decompose_note) =
        clock.stage(Stage::Ingest, || {
        let mut loaded = load_asset(path, &options.ingest)?;
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

    let interior_fill = kind.as_ref().map(|k| k.prior.interior_fill);
    let prepared = clock.stage(Stage::Prepare, || {
        // Joints refer to parts by index, so parts are never dropped here; ingest only
        // produces parts that have triangles.
        if let Some(empty) = asset.parts.iter().find(|p| p.mesh.triangle_count() == 0) {
            return Err(PipelineError::Empty(format!(
                "part {:?} of {} has no triangles",
                empty.name,
                path.display()
            )));
        }
        let offset = asset.rest_on_ground();
        notes.push(format!(
            "object moved by ({:.4}, {:.4}, {:.4}) m to rest on z = 0, centred in x and y",
            offset.x, offset.y, offset.z
        ));
        let total = asset.parts.len();
        let done = AtomicUsize::new(0);
        let prepared: Vec<PipelineResult<Prepared>> = parallel_map(&asset.parts, |part| {
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
    })?;

    let colliders = clock.stage(Stage::Colliders, || {
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
    })?;

    let (record, articulation_notes) = clock.stage(Stage::Ground, || {
        let (mut record, mut notes) =
            ground(&name, source, kind.as_ref(), &asset, &prepared, &colliders)?;
        if let Some(learned) = &options.learned {
            notes.extend(ground_learned(
                &asset,
                &prepared,
                &colliders,
                &mut record,
                learned,
            )?);
        }
        if let Some(lvlm) = &options.lvlm {
            notes.extend(ground_lvlm(
                &asset,
                &prepared,
                &colliders,
                &mut record,
                lvlm,
            )?);
        }
        let movable = record.joints.iter().filter(|j| j.kind.is_movable()).count();
        let summary = format!(
            "{} movable joints, object mass {:.3} kg ({})",
            movable, record.object.mass_kg.value, record.object.category.value
        );
        Ok(((record, notes), summary))
    })?;
    notes.extend(articulation_notes);

    let meshes: Vec<TriMesh> = asset.parts.iter().map(|p| p.mesh.clone()).collect();
    // Touching pairs serve verification (the dynamic check's contact filter) and export (MJCF
    // excludes): computed once, timed with verification.
    let (record, verified, touching) = clock.stage(Stage::Verify, || {
        let touching = touching_pairs(&asset, options.touching_fraction);
        let verified = verify(record, &meshes, &colliders, &touching, &options.verify)?;
        let summary = format!(
            "{} of {} movable joints passed the sweep, {} corrected; intrinsic {}",
            verified.joints_passed,
            verified.joints_swept,
            verified.corrections.len(),
            if verified.intrinsic_passed {
                "passed"
            } else {
                "failed"
            }
        );
        Ok(((verified.record.clone(), verified, touching), summary))
    })?;
    notes.extend(verified.corrections.iter().cloned());
    let mut colliders = colliders;
    let carved = carve_cavities(&record, &meshes, &mut colliders);
    if carved > 0 {
        notes.push(format!(
            "colliders: the hulls of {carved} parents carved around the parts jointed to them, which leaves room where they move"
        ));
    }

    let (artifacts, report) = clock.stage(Stage::Export, || {
        let colors: Vec<[f32; 4]> = asset
            .parts
            .iter()
            .map(|p| display_rgba(&p.mesh, &asset.materials, &asset.textures))
            .collect();
        let mut report = VerificationReport::default();
        report
            .sections
            .push(ingest_section(dropped, &ingest_warnings));
        report.sections.extend(verified.sections.iter().cloned());
        report.metrics.extend(verified.metrics.clone());
        let out = export(&ExportInput {
            record: &record,
            part_meshes: &meshes,
            colliders: &colliders,
            part_colors: &colors,
            materials: &asset.materials,
            textures: &asset.textures,
            touching_pairs: &touching,
            report: &report,
            notes: &notes,
        })?;
        let mut artifacts = out.artifacts;
        artifacts.push(Artifact {
            path: PREVIEW_PATH.to_owned(),
            bytes: preview_png(&meshes)?,
        });
        artifacts.sort_by(|a, b| a.path.cmp(&b.path));
        let failures = out.report.failures().count();
        let summary = format!("{} files, {} checks failed", artifacts.len(), failures);
        Ok(((artifacts, out.report), summary))
    })?;

    Ok(RunOutput {
        record,
        artifacts,
        report,
        timings: clock.timings,
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

fn ground(
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

fn touching_pairs(asset: &MeshAsset, fraction: f64) -> Vec<(PartId, PartId)> {
    let threshold = fraction * asset.bounds().diagonal();
    let n = asset.parts.len();
    let pairs: Vec<(usize, usize)> = (0..n)
        .flat_map(|i| ((i + 1)..n).map(move |j| (i, j)))
        .collect();
    let probes = parallel_map(&asset.parts, |part| DistanceProbe::new(&part.mesh));
    let close = parallel_map(&pairs, |&(i, j)| {
        probes[i].min_distance_m(&probes[j]) <= threshold
    });
    let id = |i: usize| PartId(u32::try_from(i).unwrap_or(u32::MAX));
    pairs
        .into_iter()
        .zip(close)
        .filter(|(_, c)| *c)
        .map(|((i, j), _)| (id(i), id(j)))
        .collect()
}

fn ingest_section(dropped: usize, warnings: &[String]) -> ReportSection {
    let mut checks = vec![CheckResult {
        check: "degenerate_triangles".into(),
        subject: "object".into(),
        outcome: if dropped == 0 {
            CheckOutcome::Pass
        } else {
            CheckOutcome::Warn
        },
        message: if dropped == 0 {
            "none".into()
        } else {
            format!("{dropped} zero-area triangles dropped")
        },
    }];
    checks.extend(warnings.iter().map(|w| CheckResult {
        check: "referenced_files".into(),
        subject: "object".into(),
        outcome: CheckOutcome::Warn,
        message: w.clone(),
    }));
    ReportSection {
        name: "ingest".into(),
        checks,
    }
}
