//! Ground-truth and geometry checks of every example.

mod support;

use support::{mesh_distance, surface_samples, winding_number};
use uniphys_examples::{EXAMPLE_NAMES, ExampleAsset, GlbFrame, catalogue, example, write_glb};
use uniphys_geometry::DVec3;
use uniphys_types::{JointKind, PartId, Provenance};

/// Depth below a part's surface at which its samples must be outside every other part.
const PENETRATION_TOLERANCE: f64 = 2e-4;
const MM: f64 = 1e-3;

fn part<'a>(e: &'a ExampleAsset, name: &str) -> &'a uniphys_geometry::TriMesh {
    let index = e
        .part_index(name)
        .unwrap_or_else(|| panic!("{}: no part {name}", e.name));
    &e.asset.parts[index].mesh
}

#[test]
fn every_part_is_closed_after_welding() {
    for e in catalogue() {
        for p in &e.asset.parts {
            p.mesh.validate().unwrap();
            assert!(
                p.mesh.welded(1e-9).is_closed(),
                "{}/{} is open",
                e.name,
                p.name
            );
        }
    }
}

#[test]
fn examples_rest_on_the_ground_centred_and_have_the_stated_size() {
    let sizes = [
        ("box_with_lid", [0.3, 0.2, 0.16]),
        ("cabinet", [0.6, 0.487, 0.8]),
        ("laptop", [0.32, 0.266, 0.236]),
        ("mug", [0.117, 0.08, 0.095]),
    ];
    for (name, size) in sizes {
        let e = example(name).unwrap();
        let b = e.asset.bounds();
        assert!(b.min.z.abs() < 1e-12, "{name} floats or sinks: {}", b.min.z);
        let extents = b.extents();
        for axis in 0..3 {
            assert!(
                (extents[axis] - size[axis]).abs() < 0.01,
                "{name} extent {axis}: {} vs {}",
                extents[axis],
                size[axis]
            );
        }
        let centre = b.center();
        assert!(
            centre.x.abs() < 1e-12 && centre.y.abs() < 1e-12,
            "{name} off centre: {centre}"
        );
    }
}

#[test]
fn no_part_penetrates_another() {
    for e in catalogue() {
        let parts = &e.asset.parts;
        for (i, a) in parts.iter().enumerate() {
            let samples = surface_samples(&a.mesh, 0.01, PENETRATION_TOLERANCE);
            for (j, b) in parts.iter().enumerate() {
                if i == j {
                    continue;
                }
                let bounds = b.mesh.bounds();
                let inside = samples.iter().find(|&&p| {
                    p.cmpge(bounds.min).all()
                        && p.cmple(bounds.max).all()
                        && winding_number(&b.mesh, p) > 0.5
                });
                assert!(
                    inside.is_none(),
                    "{}: {} enters {} at {:?}",
                    e.name,
                    a.name,
                    b.name,
                    inside
                );
            }
        }
    }
}

#[test]
fn connected_parts_are_within_two_millimetres_and_moving_ones_clear_by_one() {
    for e in catalogue() {
        for j in &e.expected_joints {
            let d = mesh_distance(part(&e, j.child), part(&e, j.parent));
            assert!(
                d <= 2.0 * MM + 1e-9,
                "{}: {} is {d} m from {}",
                e.name,
                j.child,
                j.parent
            );
            if j.kind.is_movable() {
                assert!(
                    d >= MM - 1e-9,
                    "{}: {} touches {} ({d} m)",
                    e.name,
                    j.child,
                    j.parent
                );
            }
        }
    }
}

#[test]
fn expected_joints_name_existing_parts_with_unit_axes_and_ordered_limits() {
    for e in catalogue() {
        for j in &e.expected_joints {
            assert!(e.part_index(j.child).is_some(), "{}: {}", e.name, j.child);
            assert!(e.part_index(j.parent).is_some(), "{}: {}", e.name, j.parent);
            assert_ne!(j.child, j.parent);
            assert!((DVec3::from_array(j.axis).length() - 1.0).abs() < 1e-12);
            assert!(j.limits.0 <= j.limits.1);
            if j.kind.is_movable() {
                assert!(
                    j.limits.0 <= 0.0 && 0.0 <= j.limits.1,
                    "pose outside limits"
                );
                assert!(j.limits.1 > 0.0, "{}: {} cannot open", e.name, j.child);
            }
        }
        let mut children: Vec<&str> = e.expected_joints.iter().map(|j| j.child).collect();
        children.sort_unstable();
        children.dedup();
        assert_eq!(
            children.len(),
            e.expected_joints.len(),
            "a part has two parents"
        );
        assert_eq!(
            children.len() + 1,
            e.asset.parts.len(),
            "{}: joints must connect all parts in a tree",
            e.name
        );
    }
}

#[test]
fn asset_joints_mirror_the_expected_joints() {
    for e in catalogue() {
        assert_eq!(e.asset.joints.len(), e.expected_joints.len(), "{}", e.name);
        for (joint, expected) in e.asset.joints.iter().zip(&e.expected_joints) {
            let id = |name| PartId(e.part_index(name).unwrap() as u32);
            assert_eq!(joint.child, id(expected.child));
            assert_eq!(joint.parent, id(expected.parent));
            assert_eq!(joint.kind, expected.kind);
            assert_eq!(joint.axis_in_object, expected.axis);
            assert_eq!(joint.pivot_in_object_m, expected.pivot);
            assert_eq!(joint.limits.is_some(), expected.kind.needs_limits());
            if let Some(limits) = joint.limits {
                assert_eq!((limits.lower, limits.upper), expected.limits);
            }
            assert_eq!(joint.provenance, Provenance::input("example generator"));
        }
    }
}

#[test]
fn the_stated_joints_are_the_ground_truth() {
    let find = |e: &ExampleAsset, child: &str| {
        e.expected_joints
            .iter()
            .find(|j| j.child == child)
            .cloned()
            .unwrap_or_else(|| panic!("{}: no joint for {child}", e.name))
    };
    let cabinet = example("cabinet").unwrap();
    let drawer = find(&cabinet, "drawer");
    assert_eq!(
        (drawer.kind, drawer.axis),
        (JointKind::Prismatic, [0.0, -1.0, 0.0])
    );
    let door = find(&cabinet, "door");
    assert_eq!(
        (door.kind, door.axis),
        (JointKind::Revolute, [0.0, 0.0, -1.0])
    );
    assert_eq!(find(&cabinet, "drawer_handle").parent, "drawer");
    assert_eq!(find(&cabinet, "door_handle").kind, JointKind::Fixed);
    let laptop = example("laptop").unwrap();
    let lid = find(&laptop, "lid");
    assert_eq!(
        (lid.kind, lid.axis),
        (JointKind::Revolute, [-1.0, 0.0, 0.0])
    );
    assert!(lid.limits.0 < -1.6 && lid.limits.1 > 0.0);
    let boxed = example("box_with_lid").unwrap();
    let box_lid = find(&boxed, "lid");
    assert_eq!(
        (box_lid.axis, box_lid.limits),
        ([-1.0, 0.0, 0.0], (0.0, 1.9))
    );
    let mug = example("mug").unwrap();
    assert!(
        mug.expected_joints
            .iter()
            .all(|j| j.kind == JointKind::Fixed)
    );
}

#[test]
fn positive_motion_opens_away_from_the_parent() {
    // Rotating the free edge of each revolute child by a small positive angle moves it out of
    // its housing: the door's free edge to -y, the lids' front edges up.
    for (name, child, direction) in [
        ("cabinet", "door", DVec3::NEG_Y),
        ("box_with_lid", "lid", DVec3::Z),
    ] {
        let e = example(name).unwrap();
        let j = e.expected_joints.iter().find(|j| j.child == child).unwrap();
        let pivot = DVec3::from_array(j.pivot);
        let axis = DVec3::from_array(j.axis);
        let b = part(&e, child).bounds();
        let far = [b.min, b.max]
            .into_iter()
            .max_by(|p, q| {
                let d = |x: &DVec3| (*x - pivot).reject_from(axis).length();
                d(p).total_cmp(&d(q))
            })
            .unwrap();
        let velocity = axis.cross(far - pivot);
        assert!(
            velocity.dot(direction) > 0.0,
            "{name}/{child} opens the wrong way"
        );
    }
}

#[test]
fn material_names_say_the_material() {
    let classes = [
        "wood_", "metal_", "plastic_", "glass_", "ceramic_", "rubber_",
    ];
    for e in catalogue() {
        for m in &e.asset.materials {
            assert!(classes.iter().any(|c| m.name.starts_with(c)), "{}", m.name);
            assert!(m.base_color_rgba.iter().all(|c| (0.0..=1.0).contains(c)));
        }
        for p in &e.asset.parts {
            assert!(p.mesh.face_materials.is_some(), "{}/{}", e.name, p.name);
        }
    }
}

#[test]
fn example_glbs_stay_small() {
    for name in EXAMPLE_NAMES {
        let bytes = write_glb(&example(name).unwrap().asset, GlbFrame::YUp).unwrap();
        assert!(bytes.len() < 200_000, "{name}.glb is {} bytes", bytes.len());
    }
}

#[test]
fn the_checks_detect_overlap_and_measure_gaps() {
    use uniphys_examples::shapes::cuboid;
    let a = cuboid(DVec3::ZERO, DVec3::ONE);
    let overlapping = cuboid(DVec3::splat(0.99), DVec3::splat(2.0));
    let samples = surface_samples(&overlapping, 0.01, PENETRATION_TOLERANCE);
    assert!(samples.iter().any(|&p| winding_number(&a, p) > 0.5));
    let touching = cuboid(DVec3::new(1.0, 0.0, 0.0), DVec3::new(2.0, 1.0, 1.0));
    let samples = surface_samples(&touching, 0.01, PENETRATION_TOLERANCE);
    assert!(samples.iter().all(|&p| winding_number(&a, p) < 0.5));
    let apart = cuboid(DVec3::new(1.0015, 0.2, 0.2), DVec3::new(2.0, 0.8, 0.8));
    assert!((mesh_distance(&a, &apart) - 0.0015).abs() < 1e-12);
}
