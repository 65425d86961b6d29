//! The entry point: validate, build the joint models, run the at-rest test once for the whole
//! asset, then one drive test per movable joint (on all cores), and collect the verdicts.

use std::time::Instant;

use uniphys_geometry::{Aabb, TriMesh, parallel_map};
use uniphys_types::{AssetRecord, CheckOutcome, PartId};

use crate::drive::{DriveSetup, run_drive};
use crate::model::joint_models;
use crate::report::{DynamicReport, JointDynamics};
use crate::rest::run_rest;
use crate::scene::Scene;
use crate::{DynamicParams, SimulateError, SimulateResult};

/// Checks the asset dynamically: at rest, then each movable joint driven to its limits.
///
/// `colliders[i]` are the convex hulls of `record.parts[i]` in the object frame at rest (the
/// pipeline's part ids equal their positions). `excluded_pairs` are part pairs whose contacts
/// are ignored, in addition to every joint's parent and child and to parts welded by fixed
/// joints (see the collision-filter policy in the crate documentation).
///
/// Returns an error only when the check cannot run (invalid record or parameters, colliders
/// that do not match the parts, unusable mass properties); a misbehaving asset is a failed
/// verdict in the report.
pub fn check_dynamics(
    record: &AssetRecord,
    colliders: &[Vec<TriMesh>],
    excluded_pairs: &[(PartId, PartId)],
    params: &DynamicParams,
) -> SimulateResult<DynamicReport> {
    let started = Instant::now();
    params.validate()?;
    record.validate()?;
    if colliders.len() != record.parts.len() {
        return Err(SimulateError::ColliderCount {
            parts: record.parts.len(),
            colliders: colliders.len(),
        });
    }
    let diagonal_m = object_diagonal_m(record, colliders);
    let models = joint_models(record, colliders, params);
    let speed_bound = params.max_speed_diagonals_per_s * diagonal_m;

    let rest_started = Instant::now();
    let mut scene = Scene::build(record, colliders, excluded_pairs, params, diagonal_m)?;
    let notes = std::mem::take(&mut scene.notes);
    let rests = run_rest(&mut scene, &models, params, speed_bound);
    let rest_time_ms = rest_started.elapsed().as_secs_f64() * 1e3;

    let rest_passed: Vec<bool> = rests
        .iter()
        .map(|r| r.verdict.outcome == CheckOutcome::Pass)
        .collect();
    let moving_mass_kg = record
        .parts
        .iter()
        .filter(|p| p.id != record.root)
        .map(|p| p.mass.mass_kg.value)
        .sum();
    let setup = DriveSetup {
        record,
        colliders,
        excluded_pairs,
        models: &models,
        rest_passed: &rest_passed,
        diagonal_m,
        moving_mass_kg,
    };
    // Each drive runs in a world of its own: independent, so on all cores.
    let indices: Vec<usize> = (0..models.len()).collect();
    let drives = parallel_map(&indices, |&k| run_drive(&setup, k, params));
    let mut joints = Vec::with_capacity(models.len());
    for ((model, rest), drive) in models.iter().zip(rests).zip(drives) {
        let (drive, drive_time_ms) = drive?;
        let verdict = rest.verdict.clone().combine(&drive.verdict);
        joints.push(JointDynamics {
            joint: model.name.clone(),
            kind: model.kind,
            rest,
            drive,
            drive_time_ms,
            verdict,
        });
    }
    Ok(DynamicReport {
        joints,
        rest_time_ms,
        total_time_ms: started.elapsed().as_secs_f64() * 1e3,
        notes,
    })
}

/// Diagonal of the bounds of all colliders (or of the parts' recorded bounds when there are no
/// colliders), m; at least 1 mm.
fn object_diagonal_m(record: &AssetRecord, colliders: &[Vec<TriMesh>]) -> f64 {
    let points = colliders
        .iter()
        .flatten()
        .flat_map(|h| h.positions.iter().copied());
    let mut bounds = Aabb::from_points(&[]);
    for p in points {
        bounds = bounds.grown(p);
    }
    if bounds.is_empty() {
        for part in &record.parts {
            for corner in part.bounds_in_object_m {
                bounds = bounds.grown(corner.into());
            }
        }
    }
    if bounds.is_empty() {
        return 1e-3;
    }
    bounds.diagonal().max(1e-3)
}
