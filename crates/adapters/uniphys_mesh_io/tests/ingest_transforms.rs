//! Ingest options that change the asset: ignored joints and a whole-asset rotation.

mod common;

use glam::{DQuat, DVec3};
use uniphys_mesh_io::{AssetRotation, IngestOptions, LoadedAsset, load_asset};

fn cabinet(options: &IngestOptions) -> (tempfile::TempDir, LoadedAsset) {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::cabinet_fixture(&dir.path().join("cabinet"));
    let loaded = load_asset(&path, options).expect("cabinet loads");
    (dir, loaded)
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn ignored_joints_keep_parts_and_names_but_drop_every_joint() {
    let (_d, plain) = cabinet(&IngestOptions::default());
    let (_e, stripped) = cabinet(&IngestOptions {
        ignore_joints: true,
        ..IngestOptions::default()
    });
    assert_eq!(plain.asset.joints.len(), 2);
    assert!(stripped.asset.joints.is_empty());
    assert_eq!(stripped.asset.parts, plain.asset.parts);
}

#[test]
fn rotation_turns_meshes_and_joint_axes_and_pivots_together() {
    let rotation = AssetRotation::from_seed(42);
    let q = rotation.rotated_from_input;
    let (_d, plain) = cabinet(&IngestOptions::default());
    let (_e, turned) = cabinet(&IngestOptions {
        rotation: Some(rotation),
        ..IngestOptions::default()
    });
    for (a, b) in plain.asset.parts.iter().zip(&turned.asset.parts) {
        for (p, r) in a.mesh.positions.iter().zip(&b.mesh.positions) {
            assert!(close(q * *p, *r), "{p} -> {r}");
        }
    }
    for (a, b) in plain.asset.joints.iter().zip(&turned.asset.joints) {
        let axis = q * DVec3::from_array(a.axis_in_object);
        let pivot = q * DVec3::from_array(a.pivot_in_object_m);
        assert!(close(axis, DVec3::from_array(b.axis_in_object)));
        assert!(close(pivot, DVec3::from_array(b.pivot_in_object_m)));
        let (la, lb) = (a.limits.expect("limits"), b.limits.expect("limits"));
        assert!(
            (la.lower - lb.lower).abs() < 1e-12 && (la.upper - lb.upper).abs() < 1e-12,
            "a rotation keeps limits: {la:?} {lb:?}"
        );
    }
}

#[test]
fn a_non_unit_rotation_is_refused_with_the_option_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::cabinet_fixture(&dir.path().join("cabinet"));
    let options = IngestOptions {
        rotation: Some(AssetRotation {
            rotated_from_input: DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0),
            seed: None,
        }),
        ..IngestOptions::default()
    };
    let err = load_asset(&path, &options).expect_err("non-unit quaternion accepted");
    assert!(err.to_string().contains("rotation"), "{err}");
}
