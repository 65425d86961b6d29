//! URDF assets: links to parts, joints in the object frame, PartNet-Mobility folders.

mod common;

use uniphys_geometry::DVec3;
use uniphys_mesh_io::{IngestOptions, LoadedAsset, load_asset};
use uniphys_types::{JointKind, JointLimits, PartId, Provenance, SourceFormat};

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (DVec3::from_array(a) - DVec3::from_array(b)).length() < 1e-9
}

fn cabinet(options: &IngestOptions) -> (tempfile::TempDir, LoadedAsset) {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = common::cabinet_fixture(&dir.path().join("cabinet"));
    let loaded = load_asset(&path, options).expect("cabinet loads");
    (dir, loaded)
}

#[test]
fn links_with_geometry_become_parts_in_file_order() {
    let (_dir, loaded) = cabinet(&IngestOptions::default());
    let names: Vec<&str> = loaded.asset.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["base", "door", "drawer"]);
    assert_eq!(loaded.source.format, SourceFormat::Urdf);
    let base = loaded.asset.parts[0].mesh.bounds();
    assert!(
        close(base.min.to_array(), [-0.5, -0.5, 0.0])
            && close(base.max.to_array(), [0.5, 0.5, 1.0])
    );
    assert!(loaded.asset.parts[0].mesh.is_closed());
    let grey = loaded.asset.parts[0]
        .mesh
        .face_materials
        .as_ref()
        .expect("materials")[0];
    assert_eq!(
        loaded.asset.materials[grey as usize].base_color_rgba,
        [0.5, 0.5, 0.5, 1.0]
    );
}

#[test]
fn mesh_visual_is_placed_by_joint_origin_and_visual_origin() {
    let (_dir, loaded) = cabinet(&IngestOptions::default());
    // door.obj spans y in [-0.25, 0.25], z in [0, 1] at x = 0; the visual shifts it 0.25 along
    // the door's x, the joint turns the door frame 90 degrees about Z and puts it at (0.5, -0.5, 0.5).
    let b = loaded.asset.parts[1].mesh.bounds();
    assert!(close(b.min.to_array(), [0.25, -0.25, 0.5]), "{:?}", b.min);
    assert!(close(b.max.to_array(), [0.75, -0.25, 1.5]), "{:?}", b.max);
    // collision-only drawer: box 0.4 x 0.4 x 0.1 at the joint origin.
    let d = loaded.asset.parts[2].mesh.bounds();
    assert!(
        close(d.min.to_array(), [-0.2, -0.2, 0.15]) && close(d.max.to_array(), [0.2, 0.2, 0.25])
    );
}

#[test]
fn joints_have_axis_pivot_limits_and_dynamics_in_the_object_frame() {
    let (_dir, loaded) = cabinet(&IngestOptions::default());
    let joints = &loaded.asset.joints;
    assert_eq!(joints.len(), 2);
    let door = &joints[0];
    assert_eq!(door.name, "door_hinge");
    assert_eq!(door.kind, JointKind::Revolute);
    assert_eq!((door.parent, door.child), (PartId(0), PartId(1)));
    assert!(
        close(door.axis_in_object, [0.0, 1.0, 0.0]),
        "{:?}",
        door.axis_in_object
    );
    assert!(close(door.pivot_in_object_m, [0.5, -0.5, 0.5]));
    assert_eq!(
        door.limits,
        Some(JointLimits {
            lower: 0.0,
            upper: 1.57
        })
    );
    assert!((door.damping - 0.1).abs() < 1e-12 && (door.friction - 0.2).abs() < 1e-12);
    assert!(door.coupled_parts.is_empty());
    assert_eq!(door.provenance, Provenance::input("urdf joint door_hinge"));
    let drawer = &joints[1];
    assert_eq!(drawer.kind, JointKind::Prismatic);
    assert_eq!((drawer.parent, drawer.child), (PartId(0), PartId(2)));
    assert!(
        close(drawer.axis_in_object, [0.0, 1.0, 0.0]),
        "axis normalised"
    );
    assert!(close(drawer.pivot_in_object_m, [0.0, 0.0, 0.2]));
    assert_eq!(
        drawer.limits,
        Some(JointLimits {
            lower: 0.0,
            upper: 0.3
        })
    );
    assert_eq!((drawer.damping, drawer.friction), (0.0, 0.0));
}

#[test]
fn unit_scale_moves_pivots_and_scales_prismatic_limits() {
    let options = IngestOptions {
        metres_per_unit: 2.0,
        ..IngestOptions::default()
    };
    let (_dir, loaded) = cabinet(&options);
    let drawer = &loaded.asset.joints[1];
    assert!(close(drawer.pivot_in_object_m, [0.0, 0.0, 0.4]));
    assert_eq!(
        drawer.limits,
        Some(JointLimits {
            lower: 0.0,
            upper: 0.6
        })
    );
    let door = &loaded.asset.joints[0];
    assert_eq!(
        door.limits,
        Some(JointLimits {
            lower: 0.0,
            upper: 1.57
        }),
        "angles unchanged"
    );
}

#[test]
fn partnet_folder_loads_its_single_urdf_with_textures_outside_the_mesh_folder() {
    let dir = tempfile::tempdir().expect("tempdir");
    let folder = common::partnet_fixture(&dir.path().join("148"));
    let loaded = load_asset(&folder, &IngestOptions::default()).expect("folder loads");
    assert_eq!(loaded.source.file_name, "mobility.urdf");
    let names: Vec<&str> = loaded.asset.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        ["link_0", "link_1"],
        "the geometry-less base is not a part"
    );
    assert_eq!(
        loaded.asset.textures.len(),
        1,
        "../images/tex.png from textured_objs/"
    );
    let wood = loaded
        .asset
        .materials
        .iter()
        .find(|m| m.name == "wood")
        .expect("wood");
    assert_eq!(wood.base_color_texture, Some(0));
    assert_eq!(
        loaded.asset.joints.len(),
        1,
        "the body's fixed joint to the empty base disappears"
    );
    let j = &loaded.asset.joints[0];
    assert_eq!(j.name, "joint_0");
    assert_eq!((j.parent, j.child), (PartId(1), PartId(0)));
    assert!(j.limits.is_some(), "limit without velocity is read");
    // joint_1 turns link_1's frame (roll 90, yaw -90 degrees); joint_0's origin and axis are
    // expressed in that frame.
    let r = glam::DMat3::from_rotation_z(-std::f64::consts::FRAC_PI_2)
        * glam::DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2);
    let expected_axis = r * DVec3::new(0.0, 0.0, -1.0);
    let expected_pivot = r * DVec3::new(0.5, 0.0, 0.0);
    assert!(
        close(j.axis_in_object, expected_axis.to_array()),
        "{:?}",
        j.axis_in_object
    );
    assert!(
        close(j.pivot_in_object_m, expected_pivot.to_array()),
        "{:?}",
        j.pivot_in_object_m
    );
}

#[test]
fn motion_across_a_link_without_geometry_is_kept_and_explained() {
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = r#"<robot name="box">
      <link name="body"><visual><geometry><box size="1 1 1"/></geometry></visual></link>
      <link name="hinge_frame"/>
      <link name="lid"><visual><origin xyz="0 0.5 0"/><geometry><box size="1 1 0.1"/></geometry></visual></link>
      <joint name="hinge" type="continuous"><origin xyz="0 -0.5 0.5"/><parent link="body"/><child link="hinge_frame"/></joint>
      <joint name="mount" type="fixed"><origin xyz="0 0 0.05"/><parent link="hinge_frame"/><child link="lid"/></joint>
    </robot>"#;
    let path = common::write(&dir.path().join("a"), "box.urdf", urdf);
    let loaded = load_asset(&path, &IngestOptions::default()).expect("loads");
    assert_eq!(loaded.asset.parts.len(), 2);
    let j = &loaded.asset.joints[0];
    assert_eq!(
        j.name, "mount",
        "named after the joint whose child is the part"
    );
    assert_eq!(j.kind, JointKind::Continuous);
    assert_eq!(j.limits, None);
    assert!(
        close(j.axis_in_object, [1.0, 0.0, 0.0]),
        "URDF default axis"
    );
    assert!(
        close(j.pivot_in_object_m, [0.0, -0.5, 0.5]),
        "pivot of the moving joint"
    );
    let Provenance::Input { detail } = &j.provenance else {
        panic!("input provenance")
    };
    assert!(
        detail.starts_with("urdf joint mount") && detail.contains("motion from urdf joint hinge"),
        "{detail}"
    );
}

#[test]
fn floating_joint_is_fixed_and_says_so_and_unlimited_revolute_keeps_no_limits() {
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = r#"<robot name="r">
      <link name="a"><visual><geometry><sphere radius="0.5"/></geometry></visual></link>
      <link name="b"><visual><geometry><cylinder radius="0.1" length="1"/></geometry></visual></link>
      <link name="c"><visual><geometry><capsule radius="0.1" length="1"/></geometry></visual></link>
      <joint name="free" type="floating"><parent link="a"/><child link="b"/></joint>
      <joint name="hinge" type="revolute"><parent link="a"/><child link="c"/><axis xyz="0 0 1"/></joint>
    </robot>"#;
    let path = common::write(&dir.path().join("a"), "r.urdf", urdf);
    let loaded = load_asset(&path, &IngestOptions::default()).expect("loads");
    let free = &loaded.asset.joints[0];
    assert_eq!(free.kind, JointKind::Fixed);
    assert_eq!(
        free.provenance,
        Provenance::input("urdf joint free; urdf joint free is floating, treated as fixed")
    );
    let hinge = &loaded.asset.joints[1];
    assert_eq!(hinge.kind, JointKind::Revolute);
    assert_eq!(
        hinge.limits, None,
        "no usable <limit>: left for later stages"
    );
    for part in &loaded.asset.parts {
        assert!(part.mesh.is_closed(), "{} primitive closed", part.name);
    }
}

#[test]
fn package_uri_meshes_resolve_next_to_the_urdf_or_in_its_parent() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pkg = dir.path().join("pkg");
    common::write(&pkg, "meshes/door.obj", common::DOOR_OBJ);
    let urdf = r#"<robot name="r"><link name="a"><visual><geometry>
        <mesh filename="package://pkg/meshes/door.obj"/></geometry></visual></link></robot>"#;
    let path = common::write(&pkg, "urdf/r.urdf", urdf);
    let loaded = load_asset(&path, &IngestOptions::default()).expect("found in the parent");
    assert_eq!(loaded.asset.parts[0].mesh.triangle_count(), 2);
}

#[test]
fn mesh_scale_is_applied_before_the_origin() {
    let dir = tempfile::tempdir().expect("tempdir");
    common::write(&dir.path().join("a"), "door.obj", common::DOOR_OBJ);
    let urdf = r#"<robot name="r"><link name="a"><visual><origin xyz="1 0 0"/><geometry>
        <mesh filename="door.obj" scale="1 2 3"/></geometry></visual></link></robot>"#;
    let path = common::write(&dir.path().join("a"), "r.urdf", urdf);
    let loaded = load_asset(&path, &IngestOptions::default()).expect("loads");
    let b = loaded.asset.parts[0].mesh.bounds();
    assert!(close(b.min.to_array(), [1.0, -0.5, 0.0]) && close(b.max.to_array(), [1.0, 0.5, 3.0]));
}

#[test]
fn zero_size_primitives_are_left_out_with_a_warning_but_negative_ones_are_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let urdf = r#"<robot name="r">
      <link name="leg"><visual><geometry><box size="0.1 0.1 0.5"/></geometry></visual></link>
      <link name="toe"><visual><geometry><sphere radius="0"/></geometry></visual></link>
      <joint name="ankle" type="fixed"><parent link="leg"/><child link="toe"/></joint>
    </robot>"#;
    let path = common::write(&dir.path().join("a"), "r.urdf", urdf);
    let loaded = load_asset(&path, &IngestOptions::default()).expect("loads");
    assert_eq!(loaded.asset.parts.len(), 1, "the toe has no surface");
    assert_eq!(loaded.warnings.len(), 1);
    assert!(
        loaded.warnings[0].contains("\"toe\""),
        "{:?}",
        loaded.warnings
    );

    let bad = urdf.replace(r#"radius="0""#, r#"radius="-1""#);
    let path = common::write(&dir.path().join("b"), "r.urdf", &bad);
    let err = load_asset(&path, &IngestOptions::default()).expect_err("negative radius");
    assert!(err.to_string().contains("finite and positive"), "{err}");
}
