//! Hand-built objects whose parts have no names (`link_0`, `link_1`): each kind of joint must be
//! found from geometry alone, with its axis (and, for a hinge, the edge it turns on).

use uniphys_examples::shapes::{cuboid, cylinder, open_top_box, quarter_turn_z_to_front};
use uniphys_geometry::{
    ConvexParams, DMat3, DMat4, DVec3, MassProperties, TriMesh, convex_decomposition,
};
use uniphys_ground::{PartInput, RigidMass, articulate};
use uniphys_types::{Joint, JointKind, PartId};

/// Articulates the meshes as parts `link_0`, `link_1`, ... (no joints declared) and returns the
/// joint of part 1.
fn joint_of_part_1(meshes: &[TriMesh]) -> Joint {
    let colliders: Vec<Vec<TriMesh>> = meshes
        .iter()
        .map(|m| convex_decomposition(m, &ConvexParams::default()).expect("hulls"))
        .collect();
    let names: Vec<String> = (0..meshes.len()).map(|i| format!("link_{i}")).collect();
    let masses: Vec<(f64, RigidMass)> = meshes
        .iter()
        .map(|m| {
            let mass = MassProperties::from_closed_mesh(m).expect("closed test shapes");
            let density = 500.0;
            (
                mass.volume_m3,
                RigidMass {
                    mass_kg: density * mass.volume_m3,
                    com: mass.com,
                    inertia_about_com_kg_m2: mass.inertia_about_com_per_density * density,
                },
            )
        })
        .collect();
    let parts: Vec<PartInput<'_>> = (0..meshes.len())
        .map(|i| PartInput {
            name: &names[i],
            mesh: &meshes[i],
            volume_m3: masses[i].0,
            mass: masses[i].1,
            colliders: &colliders[i],
        })
        .collect();
    let articulation = articulate(&parts, &[]).expect("articulation");
    assert_eq!(articulation.root, PartId(0), "{:#?}", articulation.notes);
    articulation
        .joints
        .into_iter()
        .find(|j| j.child == PartId(1))
        .expect("a joint for part 1")
}

fn axis(joint: &Joint) -> DVec3 {
    DVec3::from_array(joint.axis_in_object)
}

fn translated(mesh: TriMesh, by: DVec3) -> TriMesh {
    mesh.transformed(&DMat4::from_translation(by))
}

/// A cabinet 0.6 wide, 0.5 deep and 0.7 tall whose front (-y) is open.
fn open_front_cabinet() -> TriMesh {
    // Built open toward +z, then turned so the opening faces -y.
    open_top_box(
        DVec3::new(-0.3, -0.35, 0.0),
        DVec3::new(0.3, 0.35, 0.5),
        0.02,
    )
    .transformed(&(DMat4::from_translation(DVec3::new(0.0, 0.0, 0.35)) * quarter_turn_z_to_front()))
}

#[test]
fn a_drawer_in_an_open_front_cabinet_slides_out_of_the_front() {
    let cabinet = open_front_cabinet();
    let b = cabinet.bounds();
    // A drawer is a box open at the top, like the cabinet around it.
    let drawer = open_top_box(
        DVec3::new(-0.275, b.min.y - 0.01, 0.03),
        DVec3::new(0.275, b.max.y - 0.03, 0.3),
        0.01,
    );
    let joint = joint_of_part_1(&[cabinet, drawer]);
    assert_eq!(joint.kind, JointKind::Prismatic, "{joint:#?}");
    assert!(axis(&joint).dot(DVec3::NEG_Y) > 0.99, "{joint:#?}");
    let travel = joint.limits.expect("limits").upper;
    assert!(travel > 0.25, "slides out most of its depth: {travel}");
}

#[test]
fn a_door_with_a_handle_hinges_on_the_edge_away_from_the_handle() {
    let body = cuboid(DVec3::new(-0.3, -0.25, 0.0), DVec3::new(0.3, 0.25, 0.7));
    let panel = cuboid(DVec3::new(-0.3, -0.27, 0.0), DVec3::new(0.3, -0.25, 0.7));
    let handle = cuboid(DVec3::new(0.22, -0.31, 0.25), DVec3::new(0.25, -0.27, 0.45));
    let door = TriMesh::merge([&panel, &handle]);
    let joint = joint_of_part_1(&[body, door]);
    assert_eq!(joint.kind, JointKind::Revolute, "{joint:#?}");
    assert!(axis(&joint).z.abs() > 0.99, "a vertical hinge: {joint:#?}");
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    assert!(
        pivot.x < -0.25,
        "on the edge away from the handle: {joint:#?}"
    );
    assert!(joint.limits.expect("limits").upper >= 1.4, "{joint:#?}");
}

#[test]
fn a_door_with_a_bar_along_its_top_hinges_at_its_bottom() {
    // An oven's door on an open cabinet, taller than wide, with a bar across its top: the bar
    // is the handle, so the door drops open about its bottom edge, not about its long edge.
    let cabinet = open_front_cabinet();
    let b = cabinet.bounds();
    let (front, width, height) = (b.min.y, b.max.x - b.min.x, b.max.z - b.min.z);
    let panel = cuboid(
        DVec3::new(b.min.x, front - 0.02, b.min.z),
        DVec3::new(b.max.x, front, b.max.z),
    );
    let bar = cuboid(
        DVec3::new(
            b.min.x + 0.15 * width,
            front - 0.08,
            b.max.z - 0.06 * height,
        ),
        DVec3::new(
            b.max.x - 0.15 * width,
            front - 0.02,
            b.max.z - 0.02 * height,
        ),
    );
    let door = TriMesh::merge([&panel, &bar]);
    let joint = joint_of_part_1(&[cabinet, door]);
    assert_eq!(joint.kind, JointKind::Revolute, "{joint:#?}");
    assert!(
        axis(&joint).x.abs() > 0.99,
        "a horizontal hinge: {joint:#?}"
    );
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    assert!(
        pivot.z < b.min.z + 0.05,
        "along the bottom edge: {joint:#?}"
    );
}

#[test]
fn a_door_with_a_stepped_face_hinges_and_does_not_spin() {
    // A door whose outer face rises in three steps toward its middle: a turn about its normal
    // keeps most of its samples on its faces, but its outline does not map onto itself, so it
    // is no spinning disc: it hinges about an edge.
    let cabinet = open_front_cabinet();
    let b = cabinet.bounds();
    let front = b.min.y;
    let panel = cuboid(
        DVec3::new(b.min.x, front - 0.02, b.min.z),
        DVec3::new(b.max.x, front, b.max.z),
    );
    let steps: Vec<TriMesh> = (1..=3)
        .map(|k| {
            let (inset, rise) = (0.05 * f64::from(k), 0.008 * f64::from(k));
            cuboid(
                DVec3::new(b.min.x + inset, front - 0.02 - rise, b.min.z + inset),
                DVec3::new(b.max.x - inset, front - 0.02, b.max.z - inset),
            )
        })
        .collect();
    let door = TriMesh::merge(steps.iter().chain([&panel]));
    let joint = joint_of_part_1(&[cabinet, door]);
    assert_eq!(joint.kind, JointKind::Revolute, "{joint:#?}");
    assert!(
        axis(&joint).y.abs() < 0.1,
        "about an edge in the door's plane, not its normal: {joint:#?}"
    );
}

/// Where the middle of `part` goes when `joint` turns it a little the positive way.
fn moved_middle(joint: &Joint, part: &TriMesh, angle: f64) -> DVec3 {
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    let middle = part.bounds().center();
    pivot + DMat3::from_axis_angle(axis(joint).normalize(), angle) * (middle - pivot)
}

#[test]
fn a_door_on_a_hollow_cabinet_opens_outward_a_quarter_turn() {
    // Nothing inside the cabinet stops the door swinging in: only the hinge's stop does.
    let cabinet = open_front_cabinet();
    let b = cabinet.bounds();
    let door = cuboid(
        DVec3::new(b.min.x, b.min.y - 0.02, b.min.z),
        DVec3::new(b.max.x, b.min.y, b.max.z),
    );
    let joint = joint_of_part_1(&[cabinet, door.clone()]);
    assert_eq!(joint.kind, JointKind::Revolute, "{joint:#?}");
    let limits = joint.limits.expect("limits");
    assert!(limits.lower.abs() < 1e-9, "closed at rest: {joint:#?}");
    assert!(
        (1.4..=std::f64::consts::FRAC_PI_2 + 1e-9).contains(&limits.upper),
        "a quarter turn: {joint:#?}"
    );
    let opened = moved_middle(&joint, &door, 0.2);
    assert!(
        opened.y < door.bounds().center().y - 0.01,
        "opens out of the front, not into the cabinet: {joint:#?}"
    );
}

#[test]
fn a_screen_open_at_rest_closes_onto_its_base_and_opens_further() {
    let base = cuboid(DVec3::new(-0.15, -0.1, 0.0), DVec3::new(0.15, 0.1, 0.02));
    // The screen stands on the base's back edge, tilted back 10 degrees past upright.
    let upright = cuboid(DVec3::new(-0.15, 0.0, 0.0), DVec3::new(0.15, 0.008, 0.2));
    let tilt = DMat4::from_translation(DVec3::new(0.0, 0.1, 0.02))
        * DMat4::from_rotation_x(-10f64.to_radians());
    let screen = upright.transformed(&tilt);
    let joint = joint_of_part_1(&[base, screen]);
    assert_eq!(joint.kind, JointKind::Revolute, "{joint:#?}");
    assert!(axis(&joint).x.abs() > 0.99, "{joint:#?}");
    let limits = joint.limits.expect("limits");
    // Closing takes it about 100 degrees down onto the keyboard; it opens at most to 135
    // degrees from closed.
    assert!(
        (-1.9..=-1.4).contains(&limits.lower),
        "closes onto the base: {joint:#?}"
    );
    let total = limits.upper - limits.lower;
    assert!(
        (1.9..=0.75 * std::f64::consts::PI + 1e-9).contains(&total),
        "opens past upright, not round: {joint:#?}"
    );
}

/// A smooth cylinder of radius 0.025 about y, standing `length` out of the front face of a
/// cabinet, joined to it; its joint.
fn round_part_on_a_front_face(length: f64) -> Joint {
    let body = cuboid(DVec3::new(-0.3, -0.25, 0.0), DVec3::new(0.3, 0.25, 0.7));
    let to_front = quarter_turn_z_to_front();
    let part = translated(
        cylinder(0.025, 0.0, length, 32).transformed(&to_front),
        DVec3::new(0.1, -0.25, 0.5),
    );
    joint_of_part_1(&[body, part])
}

#[test]
fn a_round_knob_standing_out_of_a_face_spins_about_its_own_axis() {
    // As tall as it is wide: fingers pinch its sides.
    let joint = round_part_on_a_front_face(0.05);
    assert_eq!(joint.kind, JointKind::Continuous, "{joint:#?}");
    assert!(axis(&joint).y.abs() > 0.99, "{joint:#?}");
}

#[test]
fn a_smooth_squat_round_button_on_a_face_is_pushed_into_it() {
    // A fifth as tall as it is wide, smooth all round: nothing to turn it by.
    let joint = round_part_on_a_front_face(0.01);
    assert_eq!(joint.kind, JointKind::Prismatic, "{joint:#?}");
    assert!(axis(&joint).dot(DVec3::Y) > 0.99, "pushed in: {joint:#?}");
    let travel = joint.limits.expect("limits").upper;
    assert!(travel > 0.0 && travel <= 0.01, "{travel}");
}

#[test]
fn a_smooth_squat_cap_on_a_neck_spins() {
    // A bottle: a body, a neck of radius 0.03 and a cap as wide as the neck on its end. The
    // cap is as squat and smooth as a button, but no face lies beside it: it caps the neck.
    let body = cylinder(0.12, 0.0, 0.3, 48);
    let neck = cylinder(0.03, 0.3, 0.36, 32);
    let cap = cylinder(0.032, 0.36, 0.38, 32);
    let bottle = TriMesh::merge([&body, &neck]);
    let joint = joint_of_part_1(&[bottle, cap]);
    assert_eq!(joint.kind, JointKind::Continuous, "{joint:#?}");
    assert!(axis(&joint).z.abs() > 0.99, "{joint:#?}");
}

#[test]
fn a_flat_square_button_on_top_is_pushed_into_the_body() {
    let body = cuboid(DVec3::new(-0.3, -0.25, 0.0), DVec3::new(0.3, 0.25, 0.7));
    let button = cuboid(DVec3::new(0.0, 0.0, 0.7), DVec3::new(0.04, 0.04, 0.706));
    let joint = joint_of_part_1(&[body, button]);
    assert_eq!(joint.kind, JointKind::Prismatic, "{joint:#?}");
    assert!(
        axis(&joint).dot(DVec3::NEG_Z) > 0.99,
        "pushed down: {joint:#?}"
    );
    let travel = joint.limits.expect("limits").upper;
    assert!(travel > 0.0 && travel < 0.01, "{travel}");
}

#[test]
fn a_lid_on_an_open_box_hinges_about_a_horizontal_edge() {
    let base = open_top_box(
        DVec3::new(-0.2, -0.15, 0.0),
        DVec3::new(0.2, 0.15, 0.2),
        0.01,
    );
    let lid = cuboid(DVec3::new(-0.2, -0.15, 0.2), DVec3::new(0.2, 0.15, 0.215));
    let joint = joint_of_part_1(&[base, lid]);
    assert_eq!(joint.kind, JointKind::Revolute, "{joint:#?}");
    assert!(axis(&joint).z.abs() < 0.01, "{joint:#?}");
    let pivot = DVec3::from_array(joint.pivot_in_object_m);
    let a = axis(&joint);
    // The hinge runs along one of the lid's edges.
    let across = DVec3::Z.cross(a).normalize();
    let offset = pivot.dot(across).abs();
    let half_width = if a.x.abs() > 0.9 { 0.15 } else { 0.2 };
    assert!((offset - half_width).abs() < 0.02, "{joint:#?}");
}

#[test]
fn a_wheel_under_a_cart_spins_about_its_axle() {
    let cart = cuboid(DVec3::new(-0.4, -0.25, 0.15), DVec3::new(0.4, 0.25, 0.5));
    // A wheel of radius 0.15 about x, touching the cart's underside.
    let turn = DMat4::from_mat3(DMat3::from_rotation_y(std::f64::consts::FRAC_PI_2));
    let wheel = translated(
        cylinder(0.075, -0.02, 0.02, 48).transformed(&turn),
        DVec3::new(0.3, 0.0, 0.075),
    );
    let joint = joint_of_part_1(&[cart, wheel]);
    assert_eq!(joint.kind, JointKind::Continuous, "{joint:#?}");
    assert!(axis(&joint).x.abs() > 0.99, "{joint:#?}");
}

#[test]
fn a_spout_bulkier_than_its_base_hangs_from_the_base_the_object_stands_on() {
    // A faucet: the base stands on the ground; the spout above it has twice the base's box and
    // touches nothing else, so only the ground tells which part carries the other.
    let base = cuboid(DVec3::new(-0.3, -0.3, 0.0), DVec3::new(0.3, 0.3, 0.15));
    let spout = cuboid(DVec3::new(-0.3, -0.3, 0.15), DVec3::new(0.3, 0.5, 0.4));
    let joint = joint_of_part_1(&[base, spout]);
    assert_eq!(joint.parent, PartId(0), "{joint:#?}");
}
