//! The whole in-process pipeline on every example asset, written as GLB and read back: the
//! built-in grounder must find the ground-truth joints (names say which parts move, sweeps choose
//! how) and verification and export must pass their checks.

use uniphys_examples::{GlbFrame, catalogue, write_glb};
use uniphys_geometry::DVec3;
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::JointKind;

const MAX_AXIS_ERROR_DEG: f64 = 10.0;
const MAX_PIVOT_ERROR_M: f64 = 0.03;

#[test]
fn every_example_runs_and_the_grounder_finds_its_joints() {
    let dir = tempfile::tempdir().unwrap();
    for example in catalogue() {
        let path = dir.path().join(format!("{}.glb", example.name));
        std::fs::write(&path, write_glb(&example.asset, GlbFrame::YUp).unwrap()).unwrap();
        let out = run(&path, &RunOptions::default(), &NoProgress)
            .unwrap_or_else(|e| panic!("{}: {e}", example.name));
        let record = &out.record;
        assert_eq!(
            record.parts.len(),
            example.asset.parts.len(),
            "{}",
            example.name
        );
        let failures: Vec<String> = out
            .report
            .failures()
            .map(|c| format!("{} {}: {}", c.subject, c.check, c.message))
            .collect();
        assert!(failures.is_empty(), "{}: {failures:?}", example.name);

        // The pipeline rests the object on z = 0, centred in x and y: move the ground truth the same way.
        let b = example.asset.bounds();
        let offset = DVec3::new(-b.center().x, -b.center().y, -b.min.z);
        let symmetric = half_turn_symmetric(&example.asset, offset);
        for expected in &example.expected_joints {
            let child = record
                .parts
                .iter()
                .find(|p| p.name == expected.child)
                .unwrap_or_else(|| panic!("{}: no part {}", example.name, expected.child));
            let joint = record
                .joints
                .iter()
                .find(|j| j.child == child.id)
                .unwrap_or_else(|| panic!("{}: {} has no joint", example.name, expected.child));
            let parent = record.part(joint.parent).unwrap();
            assert_eq!(
                parent.name, expected.parent,
                "{}: parent of {}",
                example.name, expected.child
            );
            assert_eq!(
                joint.kind, expected.kind,
                "{}: kind of {}",
                example.name, expected.child
            );
            if expected.kind == JointKind::Fixed {
                continue;
            }
            let axis = DVec3::from_array(joint.axis_in_object);
            let mut gt_axis = DVec3::from_array(expected.axis).normalize();
            let mut gt_pivot = DVec3::from_array(expected.pivot) + offset;
            // An object that maps onto itself under a half-turn about the vertical has the
            // turned joint as well (a plain box's lid hinges on either long edge).
            let half_turn = |v: DVec3| DVec3::new(-v.x, -v.y, v.z);
            if symmetric && axis.dot(half_turn(gt_axis)) > axis.dot(gt_axis) {
                (gt_axis, gt_pivot) = (half_turn(gt_axis), half_turn(gt_pivot));
            }
            let error_deg = axis.dot(gt_axis).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(
                error_deg < MAX_AXIS_ERROR_DEG,
                "{}: axis of {} off by {error_deg:.1} deg ({axis} vs {gt_axis})",
                example.name,
                expected.child
            );
            if expected.kind == JointKind::Revolute {
                let pivot = DVec3::from_array(joint.pivot_in_object_m);
                let distance = (pivot - gt_pivot).reject_from_normalized(gt_axis).length();
                assert!(
                    distance < MAX_PIVOT_ERROR_M,
                    "{}: pivot of {} is {distance:.3} m from the hinge line",
                    example.name,
                    expected.child
                );
            }
        }
        // Every movable joint was swept; its metrics are in the report.
        let swept = out
            .report
            .sections
            .iter()
            .find(|s| s.name == "articulation")
            .expect("articulation section");
        let movable = record.joints.iter().filter(|j| j.kind.is_movable()).count();
        assert_eq!(swept.checks.len(), movable, "{}", example.name);
        for joint in record.joints.iter().filter(|j| j.kind.is_movable()) {
            let metrics = &out.report.metrics[&format!("joint {}", joint.name)];
            assert_eq!(metrics["sweep_steps"], 200.0, "{}", example.name);
            assert!(
                metrics.contains_key("dynamics_drive_budget_s"),
                "{}: {metrics:?}",
                example.name
            );
        }
        assert!(out.report.metrics["object"]["mass_relative_error"] < 1e-9);
        // Stage timings are reported for every stage, in order.
        let stages: Vec<&str> = out.timings.iter().map(|(s, _)| s.name()).collect();
        assert_eq!(
            stages,
            [
                "ingest",
                "prepare",
                "colliders",
                "ground",
                "verify",
                "export"
            ]
        );
        let paths: Vec<&str> = out.artifacts.iter().map(|a| a.path.as_str()).collect();
        for required in [
            "model.urdf",
            "model.xml",
            "record.json",
            "report.json",
            "annotations/object.json",
            "meta_data.json",
        ] {
            assert!(
                paths.contains(&required),
                "{}: missing {required}",
                example.name
            );
        }
    }
}

#[test]
fn a_missing_input_is_an_ingest_error_that_names_the_file() {
    let err = run(
        std::path::Path::new("/nonexistent/chair.glb"),
        &RunOptions::default(),
        &NoProgress,
    )
    .unwrap_err();
    assert!(err.to_string().contains("chair.glb"), "{err}");
}

/// Whether every part maps onto itself under a half-turn about the vertical line through the
/// object's centre (`offset` moves it to the pipeline's frame, centred on that line): each
/// turned vertex lands on a vertex of the same part.
fn half_turn_symmetric(asset: &uniphys_geometry::MeshAsset, offset: DVec3) -> bool {
    let tolerance = 1e-6 * asset.bounds().diagonal();
    asset.parts.iter().all(|part| {
        let vertices: Vec<DVec3> = part.mesh.positions.iter().map(|p| *p + offset).collect();
        vertices.iter().all(|v| {
            let turned = DVec3::new(-v.x, -v.y, v.z);
            vertices.iter().any(|w| w.distance(turned) <= tolerance)
        })
    })
}
