//! The `verify` and `export` stages of a run: the grounded record checked (intrinsic levels,
//! articulation sweeps with correction) into a [`VerifiedAsset`], which the queue stores so that
//! a retried export checks nothing again; then the parents' colliders carved where their parts
//! move, and every file written.

use uniphys_export::{Artifact, ExportInput, export};
use uniphys_geometry::{DistanceProbe, MeshAsset, TriMesh, display_rgba, parallel_map};
use uniphys_types::{
    AssetRecord, CheckOutcome, CheckResult, PartId, ReportSection, VerificationReport,
    VerifiedAsset,
};

use crate::cavities::carve_cavities;
use crate::input::Input;
use crate::preview::{PREVIEW_PATH, preview_png};
use crate::run::{Clock, RunOptions};
use crate::verify::{VerifyOptions, verify};
use crate::{PipelineResult, Stage};

/// What the last stage produced.
pub(crate) struct Finished {
    /// The verified record (corrections applied).
    pub(crate) record: AssetRecord,
    /// Exported files, sorted by path.
    pub(crate) artifacts: Vec<Artifact>,
    /// Every check that ran.
    pub(crate) report: VerificationReport,
}

/// The verify stage's options for `input`: a slide's slot may be walled by any still part when
/// its parts were cut by a decomposition (`SweepParams::slot_walled_by_any_still_part`).
fn verify_options(input: &Input, options: &RunOptions) -> VerifyOptions {
    let mut verify = options.verify.clone();
    verify.sweep.slot_walled_by_any_still_part |= input.decomposed;
    verify
}

/// The `verify` stage: `record` (grounded on `input`'s parts, whose meshes are `meshes`
/// ([`part_meshes`]), with `colliders`) checked and its failing joints corrected.
pub(crate) fn verify_grounded(
    input: &Input,
    meshes: &[TriMesh],
    record: AssetRecord,
    colliders: &[Vec<TriMesh>],
    options: &RunOptions,
    clock: &mut Clock<'_>,
) -> PipelineResult<VerifiedAsset> {
    let asset = &input.asset;
    clock.stage(Stage::Verify, || {
        // Touching pairs serve verification (the dynamic check's contact filter) and export
        // (MJCF excludes): computed once, timed with verification.
        let touching = touching_pairs(asset, options.touching_fraction);
        let verified = verify(
            record,
            meshes,
            colliders,
            touching,
            &verify_options(input, options),
        )?;
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
        Ok((verified, summary))
    })
}

/// The `export` stage: the parents' colliders carved where their parts move, and every file of
/// `verified` (on `input`'s parts, whose meshes are `meshes`) written; `notes` are what the
/// stages before verification did.
pub(crate) fn export_verified(
    input: &Input,
    meshes: &[TriMesh],
    verified: VerifiedAsset,
    mut colliders: Vec<Vec<TriMesh>>,
    mut notes: Vec<String>,
    clock: &mut Clock<'_>,
) -> PipelineResult<Finished> {
    let asset = &input.asset;
    let VerifiedAsset {
        record,
        sections,
        metrics,
        corrections,
        touching,
        ..
    } = verified;
    notes.extend(corrections);
    let carved = carve_cavities(&record, meshes, &mut colliders);
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
            .push(ingest_section(input.dropped, &input.warnings));
        report.sections.extend(sections);
        report.metrics.extend(metrics);
        let out = export(&ExportInput {
            record: &record,
            part_meshes: meshes,
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
            bytes: preview_png(meshes)?,
        });
        artifacts.sort_by(|a, b| a.path.cmp(&b.path));
        let failures = out.report.failures().count();
        let summary = format!("{} files, {} checks failed", artifacts.len(), failures);
        Ok(((artifacts, out.report), summary))
    })?;
    Ok(Finished {
        record,
        artifacts,
        report,
    })
}

/// The meshes of `asset`'s parts, in part order (what verification and export take).
pub(crate) fn part_meshes(asset: &MeshAsset) -> Vec<TriMesh> {
    asset.parts.iter().map(|p| p.mesh.clone()).collect()
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
