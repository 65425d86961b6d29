//! Export of a hand-built two-part asset (a base block and a hinged door), parsed back.
#![expect(clippy::unwrap_used, reason = "test fixtures fail loudly on purpose")]

use uniphys_export::{ExportInput, export};
use uniphys_geometry::{DVec3, TriMesh};
use uniphys_types::{
    AssetRecord, Descriptions, Estimate, Joint, JointKind, JointLimits, Material, ObjectProperties,
    PartId, PartMass, PartProperties, PartRecord, Provenance, SourceFormat, SourceInfo, UpAxis,
    VerificationReport,
};

fn block(min: DVec3, max: DVec3) -> TriMesh {
    TriMesh::cuboid(min, max)
}

fn props(material: &str) -> PartProperties {
    let e = |v: f64| Estimate::new(v, Provenance::rule("test"));
    PartProperties {
        material: Estimate::new(Material::parse(material).unwrap(), Provenance::rule("test")),
        density_kg_per_m3: e(700.0),
        youngs_modulus_pa: e(1e10),
        hardness_pa: e(1e8),
        poisson_ratio: e(0.3),
        friction_coefficient: e(0.5),
        affordance_rank: Estimate::new(2, Provenance::rule("test")),
        graspable: Estimate::new(true, Provenance::rule("test")),
        descriptions: Descriptions::default(),
    }
}

fn part(id: u32, name: &str, min: DVec3, max: DVec3) -> PartRecord {
    let ext = max - min;
    let volume = ext.x * ext.y * ext.z;
    let mass = 700.0 * volume;
    let c = (min + max) / 2.0;
    let i = |a: f64, b: f64| mass * (a * a + b * b) / 12.0;
    PartRecord {
        id: PartId(id),
        name: name.into(),
        triangle_count: 12,
        bounds_in_object_m: [min.to_array(), max.to_array()],
        properties: props("wood/oak"),
        mass: PartMass {
            volume_m3: volume,
            volume_method: "closed_mesh".into(),
            mass_kg: Estimate::new(mass, Provenance::rule("density_times_volume")),
            com_in_object_m: c.to_array(),
            inertia_about_com_kg_m2: [
                [i(ext.y, ext.z), 0.0, 0.0],
                [0.0, i(ext.x, ext.z), 0.0],
                [0.0, 0.0, i(ext.x, ext.y)],
            ],
        },
    }
}

fn record() -> (AssetRecord, Vec<TriMesh>) {
    let base = (DVec3::new(-0.3, -0.2, 0.0), DVec3::new(0.3, 0.2, 0.6));
    let door = (DVec3::new(-0.3, -0.22, 0.0), DVec3::new(0.3, -0.205, 0.6));
    let record = AssetRecord {
        schema_version: 1,
        name: "box door".into(),
        source: SourceInfo {
            file_name: "x.glb".into(),
            format: SourceFormat::Glb,
            content_sha256: "00".into(),
            metres_per_unit: 1.0,
            up_axis: UpAxis::Y,
        },
        object: ObjectProperties {
            name: Estimate::new("cabinet".into(), Provenance::rule("t")),
            category: Estimate::new("Furniture/StorageFurniture".into(), Provenance::rule("t")),
            dimensions_m: Estimate::new([0.6, 0.42, 0.6], Provenance::rule("t")),
            mass_kg: Estimate::new(100.0, Provenance::rule("t")),
        },
        parts: vec![
            part(0, "body", base.0, base.1),
            part(1, "door", door.0, door.1),
        ],
        root: PartId(0),
        joints: vec![Joint {
            name: "hinge_door".into(),
            kind: JointKind::Revolute,
            parent: PartId(0),
            child: PartId(1),
            axis_in_object: [0.0, 0.0, 1.0],
            pivot_in_object_m: [-0.3, -0.21, 0.3],
            limits: Some(JointLimits {
                lower: 0.0,
                upper: 1.5,
            }),
            damping: 0.2,
            friction: 0.01,
            coupled_parts: vec![],
            provenance: Provenance::rule("t"),
        }],
    };
    let meshes = vec![block(base.0, base.1), block(door.0, door.1)];
    (record, meshes)
}

fn run_export() -> uniphys_export::ExportOutput {
    let (record, meshes) = record();
    let colliders: Vec<Vec<TriMesh>> = meshes.iter().map(|m| vec![m.clone()]).collect();
    export(&ExportInput {
        record: &record,
        part_meshes: &meshes,
        colliders: &colliders,
        part_colors: &[[0.5, 0.3, 0.1, 1.0]; 2],
        materials: &[],
        textures: &[],
        touching_pairs: &[(PartId(0), PartId(1))],
        report: &VerificationReport::default(),
        notes: &[],
    })
    .unwrap()
}

fn text(out: &uniphys_export::ExportOutput, path: &str) -> String {
    String::from_utf8(
        out.artifacts
            .iter()
            .find(|a| a.path == path)
            .unwrap_or_else(|| panic!("no {path}"))
            .bytes
            .clone(),
    )
    .unwrap()
}

#[test]
fn urdf_has_world_link_limits_dynamics_and_inertia_at_the_com() {
    let out = run_export();
    let robot = urdf_rs::read_from_string(&text(&out, "model.urdf")).unwrap();
    let names: Vec<&str> = robot.links.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["world", "part_0_body", "part_1_door"]);
    let door = &robot.links[2];
    assert!((door.inertial.mass.value - 700.0 * 0.6 * 0.015 * 0.6).abs() < 1e-9);
    // The door frame is at the pivot; its centre of mass sits 0.3 m along +x and 0.0025 m along -y of it.
    let com = door.inertial.origin.xyz.0;
    assert!(
        (com[0] - 0.3).abs() < 1e-9 && (com[1] + 0.0025).abs() < 1e-9 && com[2].abs() < 1e-9,
        "{com:?}"
    );
    assert_eq!(door.collision.len(), 1);
    let hinge = robot
        .joints
        .iter()
        .find(|j| j.name == "hinge_door")
        .unwrap();
    assert!(matches!(hinge.joint_type, urdf_rs::JointType::Revolute));
    assert_eq!((hinge.limit.lower, hinge.limit.upper), (0.0, 1.5));
    assert_eq!(hinge.origin.xyz.0, [-0.3, -0.21, 0.3]);
    assert_eq!(hinge.dynamics.as_ref().unwrap().damping, 0.2);
    let world = robot
        .joints
        .iter()
        .find(|j| j.name == "world_fixed")
        .unwrap();
    assert_eq!(world.parent.link, "world");
}

#[test]
fn mjcf_nests_the_door_with_its_joint_and_separates_visual_from_collision() {
    let out = run_export();
    let mjcf = text(&out, "model.xml");
    assert!(mjcf.contains(
        r#"<compiler angle="radian" meshdir="meshes" texturedir="meshes" autolimits="true"/>"#
    ));
    let body = mjcf.find(r#"<body name="part_0_body""#).unwrap();
    let door = mjcf
        .find(r#"<body name="part_1_door" pos="-0.3 -0.21 0.3">"#)
        .unwrap();
    assert!(door > body);
    assert!(mjcf.contains(r#"<joint name="hinge_door" type="hinge" pos="0 0 0" axis="0 0 1" range="0 1.5" solreflimit="0.004 1" damping="0.2" frictionloss="0.01" armature="0.02"/>"#), "{mjcf}");
    assert!(mjcf.contains(r#"contype="0" conaffinity="0" group="2""#));
    // MuJoCo's parent filter skips the root, which is welded to the world: the door and its
    // body need an exclude, or their hulls fight at rest. It is written once and reported.
    assert_eq!(
        mjcf.matches(r#"<exclude body1="part_0_body" body2="part_1_door"/>"#)
            .count(),
        1,
        "{mjcf}"
    );
    let report: serde_json::Value = serde_json::from_str(&text(&out, "report.json")).unwrap();
    assert_eq!(
        report["contact_excludes"],
        serde_json::json!([{ "links": ["part_0_body", "part_1_door"], "why": "jointed" }])
    );
}

#[test]
fn link_meshes_are_in_the_link_frame_and_part_meshes_in_the_object_frame() {
    let out = run_export();
    let link = text(&out, "meshes/part_1_visual.obj");
    let part = text(&out, "parts/part_1.obj");
    // First vertex (-0.3, -0.22, 0) relative to the pivot (-0.3, -0.21, 0.3).
    assert!(link.contains("v 0 -0.01 -0.3\n"), "{link}");
    assert!(part.contains("v -0.3 -0.22 0\n"));
    assert!(part.starts_with("# written by uniphys\nmtllib part_1.mtl\n"));
    assert!(part.contains("usemtl default\n"));
}

#[test]
fn record_annotations_use_dataset_units_and_report_counts_provenance() {
    let out = run_export();
    let ann: serde_json::Value =
        serde_json::from_str(&text(&out, "annotations/part_1.json")).unwrap();
    assert_eq!(ann["basic_info"]["density"], 0.7);
    assert_eq!(ann["basic_info"]["young"], 10.0);
    assert_eq!(ann["kinematic_info"]["motion_types"][0], "C");
    assert_eq!(ann["kinematic_info"]["motion_info"]["C"]["range"][1], 1.5);
    assert_eq!(ann["kinematic_info"]["motion_info"]["dependency"][0], 1);
    let report: serde_json::Value = serde_json::from_str(&text(&out, "report.json")).unwrap();
    assert!(report["provenance_counts"]["rule:test"].as_u64().unwrap() > 10);
    assert_eq!(report["summary"]["movable_joints"], 1);
}

#[test]
fn export_rejects_inputs_that_do_not_match_the_record() {
    let (record, meshes) = record();
    let err = export(&ExportInput {
        record: &record,
        part_meshes: &meshes[..1],
        colliders: &[],
        part_colors: &[],
        materials: &[],
        textures: &[],
        touching_pairs: &[],
        report: &VerificationReport::default(),
        notes: &[],
    })
    .unwrap_err();
    assert!(err.to_string().contains("2 parts but 1 meshes"), "{err}");
}

#[test]
fn usd_stage_places_the_door_joint_about_x_turned_onto_its_axis_with_limits_in_degrees() {
    let out = run_export();
    let usd = text(&out, "model.usda");
    assert!(usd.starts_with("#usda 1.0\n"));
    assert!(usd.contains("metersPerUnit = 1\n") && usd.contains("upAxis = \"Z\"\n"));
    let joint = &usd[usd
        .find(r#"def PhysicsRevoluteJoint "hinge_door""#)
        .expect("the door's joint")..];
    let joint = &joint[..joint.find("\n    }\n").expect("end of the joint")];
    assert!(
        joint.contains("rel physics:body0 = </box_door/part_0_body>"),
        "{joint}"
    );
    assert!(
        joint.contains("rel physics:body1 = </box_door/part_1_door>"),
        "{joint}"
    );
    assert!(
        joint.contains("point3f physics:localPos0 = (-0.3, -0.21, 0.3)"),
        "{joint}"
    );
    // +X turned onto +Z: a quarter turn about -Y.
    assert!(
        joint.contains("quatf physics:localRot0 = (0.7071067812, 0, -0.7071067812, 0)"),
        "{joint}"
    );
    assert!(joint.contains("float physics:lowerLimit = 0\n"), "{joint}");
    assert!(
        joint.contains("float physics:upperLimit = 85.94366927\n"),
        "{joint}"
    );
    // 0.2 N m s per radian is 0.00349 per degree.
    assert!(
        joint.contains("float drive:angular:physics:damping = 0.003490658504\n"),
        "{joint}"
    );
    assert!(
        joint.contains("float drive:angular:physics:stiffness = 0\n"),
        "{joint}"
    );
    assert!(usd.contains("def PhysicsFixedJoint \"world_fixed\""));
    assert_eq!(
        usd.matches("\"PhysicsCollisionAPI\"").count(),
        2,
        "one hull per part"
    );
}

/// The door with a handle welded to it whose hull reaches the body at rest (as a handle by the
/// hinge does): a pair no joint connects, whose contacts must be off in every format.
fn run_export_with_handle() -> uniphys_export::ExportOutput {
    let (mut record, mut meshes) = record();
    let handle = (
        DVec3::new(-0.28, -0.24, 0.25),
        DVec3::new(-0.26, -0.2, 0.35),
    );
    record.parts.push(part(2, "handle", handle.0, handle.1));
    meshes.push(block(handle.0, handle.1));
    record.joints.push(Joint {
        name: "handle_weld".into(),
        kind: JointKind::Fixed,
        parent: PartId(1),
        child: PartId(2),
        axis_in_object: [0.0, 0.0, 1.0],
        pivot_in_object_m: [-0.27, -0.22, 0.3],
        limits: None,
        damping: 0.0,
        friction: 0.0,
        coupled_parts: vec![],
        provenance: Provenance::rule("t"),
    });
    let colliders: Vec<Vec<TriMesh>> = meshes.iter().map(|m| vec![m.clone()]).collect();
    export(&ExportInput {
        record: &record,
        part_meshes: &meshes,
        colliders: &colliders,
        part_colors: &[[0.5, 0.3, 0.1, 1.0]; 3],
        materials: &[],
        textures: &[],
        touching_pairs: &[(PartId(2), PartId(0)), (PartId(0), PartId(1))],
        report: &VerificationReport::default(),
        notes: &[],
    })
    .unwrap()
}

#[test]
fn a_pair_touching_at_rest_without_a_joint_is_off_in_the_srdf_the_usd_and_the_mjcf() {
    let out = run_export_with_handle();
    let srdf = text(&out, "model.srdf");
    let pairs: Vec<&str> = srdf
        .lines()
        .filter(|l| l.contains("<disable_collisions"))
        .map(str::trim)
        .collect();
    assert_eq!(
        pairs,
        [
            r#"<disable_collisions link1="part_0_body" link2="part_1_door" reason="Adjacent"/>"#,
            r#"<disable_collisions link1="part_0_body" link2="part_2_handle" reason="Default"/>"#,
            r#"<disable_collisions link1="part_1_door" link2="part_2_handle" reason="Adjacent"/>"#,
        ],
        "{srdf}"
    );
    let usd = text(&out, "model.usda");
    let body = &usd[usd.find(r#"def Xform "part_0_body""#).unwrap()..];
    let body = &body[..body.find("xformOp:translate").unwrap()];
    assert!(
        body.contains(r#"["PhysicsRigidBodyAPI", "PhysicsMassAPI", "PhysicsFilteredPairsAPI"]"#)
            && body.contains("rel physics:filteredPairs = [</box_door/part_2_handle>]"),
        "{body}"
    );
    // Jointed bodies are not filtered pairs: UsdPhysics joints leave their collisions off.
    assert_eq!(usd.matches("physics:filteredPairs").count(), 1, "{usd}");
    let mjcf = text(&out, "model.xml");
    assert!(mjcf.contains(r#"<exclude body1="part_0_body" body2="part_2_handle"/>"#));
}
