//! Restoration of model answers to the object frame and SI units, and refusal of bad answers.

use std::f64::consts::{PI, TAU};

use uniphys_geometry::DVec3;
use uniphys_types::{JointKind, PartId, Provenance};
use uniphys_uniphysgen::contract::{AxisAnswer, ObjectAnswer, PartAnswer, PhysicsAnswer};
use uniphys_uniphysgen::restore::{
    restore_axis, restore_members, restore_motion, restore_object, restore_physics,
};
use uniphys_uniphysgen::{CoordinateFrame, axis_from_spherical_deg};

/// centre (1, 2, 3) m, scale 0.5 m per model unit, min bound (-1, -1, -1).
fn frame() -> CoordinateFrame {
    CoordinateFrame {
        center_in_source_m: DVec3::new(1.0, 2.0, 3.0),
        scale_m: 0.5,
        min_bound: DVec3::splat(-1.0),
    }
}

fn motion(kind: Option<&str>, theta: f64, phi: f64) -> PartAnswer {
    PartAnswer {
        id: "4".to_owned(),
        motion_type: kind.map(str::to_owned),
        axis: Some(AxisAnswer::Spherical { theta, phi }),
        pivot: Some([1.0, 1.5, 2.0]),
        range: Some([0.25, 0.0]),
        ..PartAnswer::default()
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-12
}

#[test]
fn spherical_angles_follow_the_physics_convention_including_the_poles() {
    // theta from +z, phi from +x towards +y.
    assert!(close(axis_from_spherical_deg(0.0, 0.0), DVec3::Z));
    assert!(close(axis_from_spherical_deg(0.0, 123.0), DVec3::Z));
    assert!(close(axis_from_spherical_deg(180.0, 45.0), -DVec3::Z));
    assert!(close(axis_from_spherical_deg(90.0, 0.0), DVec3::X));
    assert!(close(axis_from_spherical_deg(90.0, 90.0), DVec3::Y));
    assert!(close(axis_from_spherical_deg(90.0, 270.0), -DVec3::Y));
    // theta 60, phi 180: (-sin 60, 0, cos 60) = (-0.8660254, 0, 0.5).
    let v = axis_from_spherical_deg(60.0, 180.0);
    assert!(
        close(v, DVec3::new(-(3.0f64.sqrt()) / 2.0, 0.0, 0.5)),
        "{v}"
    );
}

#[test]
fn a_vector_axis_is_normalised_and_a_zero_one_refused() {
    let axis = restore_axis("1", &AxisAnswer::Vector([0.0, 0.0, -2.0])).unwrap();
    assert!(close(axis, -DVec3::Z));
    let error = restore_axis("1", &AxisAnswer::Vector([0.0; 3])).unwrap_err();
    assert!(error.to_string().contains("zero vector"), "{error}");
}

#[test]
fn revolute_answer_restores_pivot_through_the_frame_and_range_in_radians() {
    let restored = restore_motion(&motion(Some("C"), 90.0, 0.0), &frame(), DVec3::ZERO, "ckpt")
        .unwrap()
        .unwrap();
    assert_eq!(restored.kind, JointKind::Revolute);
    assert!(close(DVec3::from_array(restored.axis_in_object), DVec3::X));
    // (pivot + min_bound) * scale + center = ((0, 0.5, 1) * 0.5) + (1, 2, 3) = (1, 2.25, 3.5).
    assert!(close(
        DVec3::from_array(restored.pivot_in_object_m),
        DVec3::new(1.0, 2.25, 3.5)
    ));
    // [0.25, 0] of a turn, sorted: [0, pi/2].
    let limits = restored.limits.unwrap();
    assert_eq!(limits.lower, 0.0);
    assert!((limits.upper - PI / 2.0).abs() < 1e-12);
    assert_eq!(
        restored.provenance,
        Provenance::provider("uniphysgen", "ckpt")
    );
}

#[test]
fn prismatic_range_is_scaled_to_metres_and_a_missing_pivot_uses_the_part_centre() {
    let mut answer = motion(Some("B"), 0.0, 0.0);
    answer.pivot = None;
    answer.range = Some([0.0, 0.8]);
    let center = DVec3::new(0.1, 0.2, 0.3);
    let restored = restore_motion(&answer, &frame(), center, "ckpt")
        .unwrap()
        .unwrap();
    assert_eq!(restored.kind, JointKind::Prismatic);
    assert_eq!(restored.pivot_in_object_m, center.to_array());
    // 0.8 model units * 0.5 m = 0.4 m.
    let limits = restored.limits.unwrap();
    assert!((limits.upper - 0.4).abs() < 1e-12 && limits.lower == 0.0);
}

#[test]
fn pivot_round_trips_source_to_model_to_source() {
    let frame = frame();
    let pivot_in_source_m = DVec3::new(0.37, -1.2, 4.05);
    let mut answer = motion(Some("C"), 10.0, 20.0);
    answer.pivot = Some(frame.point_source_to_model(pivot_in_source_m).to_array());
    let restored = restore_motion(&answer, &frame, DVec3::ZERO, "ckpt")
        .unwrap()
        .unwrap();
    let back = DVec3::from_array(restored.pivot_in_object_m);
    assert!((back - pivot_in_source_m).length() <= 1e-6 * pivot_in_source_m.length());
    let turn = restore_motion(
        &PartAnswer {
            range: Some([0.0, 1.0]),
            ..answer
        },
        &frame,
        DVec3::ZERO,
        "ckpt",
    )
    .unwrap()
    .unwrap();
    assert!((turn.limits.unwrap().upper - TAU).abs() < 1e-12);
}

#[test]
fn a_part_that_does_not_move_has_no_motion_but_a_range_without_motion_is_refused() {
    let still = PartAnswer {
        id: "2".to_owned(),
        ..PartAnswer::default()
    };
    assert_eq!(
        restore_motion(&still, &frame(), DVec3::ZERO, "m").unwrap(),
        None
    );
    let error = restore_motion(&motion(None, 0.0, 0.0), &frame(), DVec3::ZERO, "m").unwrap_err();
    assert!(error.to_string().contains("null motion_type"), "{error}");
}

#[test]
fn bad_motion_answers_are_refused_with_the_reason() {
    let error = restore_motion(&motion(Some("A"), 0.0, 0.0), &frame(), DVec3::ZERO, "m")
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("\"A\"") && error.contains("part \"4\""),
        "{error}"
    );
    let error = restore_motion(
        &motion(Some("C"), f64::NAN, 0.0),
        &frame(),
        DVec3::ZERO,
        "m",
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("not finite"), "{error}");
    let mut no_axis = motion(Some("C"), 0.0, 0.0);
    no_axis.axis = None;
    let error = restore_motion(&no_axis, &frame(), DVec3::ZERO, "m").unwrap_err();
    assert!(error.to_string().contains("no axis"), "{error}");
    let mut infinite_range = motion(Some("B"), 0.0, 0.0);
    infinite_range.range = Some([0.0, f64::INFINITY]);
    assert!(restore_motion(&infinite_range, &frame(), DVec3::ZERO, "m").is_err());
}

#[test]
fn members_are_checked_against_the_part_ids() {
    let ids: Vec<String> = ["0", "1", "2"].map(str::to_owned).to_vec();
    let answer = PartAnswer {
        id: "1".to_owned(),
        members: Some(vec!["1".to_owned(), "2".to_owned(), "1".to_owned()]),
        ..PartAnswer::default()
    };
    assert_eq!(
        restore_members(&answer, &ids).unwrap(),
        [PartId(1), PartId(2)]
    );
    let unknown = PartAnswer {
        members: Some(vec!["7".to_owned()]),
        ..answer
    };
    let error = restore_members(&unknown, &ids).unwrap_err().to_string();
    assert!(error.contains("\"7\" is not a part"), "{error}");
}

fn physics() -> PhysicsAnswer {
    PhysicsAnswer {
        material: "metal/steel".to_owned(),
        density: 7.85,
        young: 200.0,
        hardness: 150.0,
        poisson: 0.3,
        friction: 0.5,
        affordance: Some(3),
        graspable: None,
    }
}

#[test]
fn physics_is_converted_to_si_with_provider_provenance() {
    let properties = restore_physics("1", &physics(), "ckpt").unwrap();
    assert_eq!(properties.material.value.subtype, "steel");
    // 7.85 g/cm^3 = 7850 kg/m^3; 200 GPa = 2e11 Pa; 150 HV = 150 * 9.807e6 Pa = 1.47105e9 Pa.
    assert!((properties.density_kg_per_m3.value - 7850.0).abs() < 1e-9);
    assert!((properties.youngs_modulus_pa.value - 2e11).abs() < 1e-3);
    assert!((properties.hardness_pa.value - 1.47105e9).abs() < 1e-3);
    assert_eq!(properties.affordance_rank.value, 3);
    assert_eq!(
        properties.density_kg_per_m3.provenance,
        Provenance::provider("uniphysgen", "ckpt")
    );
    // graspable was not given: a default that says so.
    assert!(matches!(
        properties.graspable.provenance,
        Provenance::Default { .. }
    ));
}

#[test]
fn impossible_physics_is_refused() {
    let bad_poisson = PhysicsAnswer {
        poisson: 0.7,
        ..physics()
    };
    let error = restore_physics("1", &bad_poisson, "m")
        .unwrap_err()
        .to_string();
    assert!(error.contains("poisson 0.7"), "{error}");
    let bad_material = PhysicsAnswer {
        material: "unobtainium".to_owned(),
        ..physics()
    };
    assert!(restore_physics("1", &bad_material, "m").is_err());
    let zero_density = PhysicsAnswer {
        density: 0.0,
        ..physics()
    };
    assert!(restore_physics("1", &zero_density, "m").is_err());
}

#[test]
fn object_answer_is_converted_from_cm_to_metres() {
    let answer = ObjectAnswer {
        object_name: "cabinet".to_owned(),
        category: "Furniture/Cabinet".to_owned(),
        dimension: Some([80.0, 40.0, 120.0]),
        volume: Some(1000.0),
        mass: 25.0,
    };
    let restored = restore_object(&answer, "ckpt").unwrap();
    let dims = restored.dimensions_m.unwrap().value;
    assert!((dims[0] - 0.8).abs() < 1e-12 && (dims[2] - 1.2).abs() < 1e-12);
    // 1000 cm^3 = 1e-3 m^3.
    assert!((restored.volume_m3.unwrap().value - 1e-3).abs() < 1e-15);
    assert_eq!(restored.mass_kg.value, 25.0);
    let negative = ObjectAnswer {
        mass: -1.0,
        ..answer
    };
    assert!(restore_object(&negative, "ckpt").is_err());
}
