//! Sweeps of the example assets: their true joints pass, deliberately wrong ones fail and are
//! corrected.

use uniphys_geometry::{ConvexParams, DVec3, TriMesh, convex_decomposition};
use uniphys_types::{Joint, JointLimits};
use uniphys_verify::{Scene, SweepParams, correct_joint, moving_group, sweep, verify_articulation};

struct Fixture {
    scene: Scene,
    joints: Vec<Joint>,
    names: Vec<String>,
}

fn fixture(name: &str) -> Fixture {
    let example = uniphys_examples::example(name).expect("example exists");
    let meshes: Vec<TriMesh> = example.asset.parts.iter().map(|p| p.mesh.clone()).collect();
    let colliders: Vec<Vec<TriMesh>> = meshes
        .iter()
        .map(|m| convex_decomposition(m, &ConvexParams::default()).expect("hulls"))
        .collect();
    Fixture {
        scene: Scene::new(&meshes, &colliders, 1500).expect("scene"),
        joints: example.asset.joints.clone(),
        names: example.asset.parts.iter().map(|p| p.name.clone()).collect(),
    }
}

impl Fixture {
    fn joint(&self, child: &str) -> Joint {
        self.joints
            .iter()
            .find(|j| self.names[j.child.0 as usize] == child)
            .expect("joint")
            .clone()
    }

    fn failures(&self, joint: &Joint) -> Vec<String> {
        let params = SweepParams::default();
        let moving = moving_group(&self.joints, joint.child);
        sweep(&self.scene, joint, &moving, &params)
            .expect("sweep")
            .failures(&params)
    }

    fn corrected(&self, joint: &Joint) -> Joint {
        let params = SweepParams::default();
        let moving = moving_group(&self.joints, joint.child);
        let fix = correct_joint(&self.scene, joint, &moving, &params)
            .expect("correction runs")
            .expect("a variant passes");
        assert!(fix.metrics.failures(&params).is_empty());
        fix.joint
    }
}

#[test]
fn true_joints_of_every_example_pass() {
    for name in uniphys_examples::EXAMPLE_NAMES {
        let f = fixture(name);
        let outcome = verify_articulation(&f.scene, &f.joints, &SweepParams::default(), false)
            .expect("verification runs");
        assert!(outcome.passed(), "{name}: {:#?}", outcome.section.checks);
        let movable = f.joints.iter().filter(|j| j.kind.is_movable()).count();
        assert_eq!(outcome.section.checks.len(), movable, "{name}");
        assert_eq!(outcome.metrics.len(), movable, "{name}");
    }
}

#[test]
fn a_door_turning_inwards_passes_through_the_carcass_and_is_reversed() {
    let f = fixture("cabinet");
    let mut door = f.joint("door");
    door.axis_in_object = (-DVec3::from_array(door.axis_in_object)).to_array();
    let reasons = f.failures(&door);
    assert!(
        reasons.iter().any(|r| r.contains("passes through")),
        "{reasons:?}"
    );
    let fixed = f.corrected(&door);
    // Reversing the range of the flipped axis is the true motion again.
    let limits = fixed.limits.expect("limits");
    let motion = DVec3::from_array(fixed.axis_in_object) * limits.upper.signum();
    assert!(motion.dot(DVec3::NEG_Z) > 0.99, "{fixed:?}");
}

#[test]
fn a_drawer_sliding_backwards_passes_through_the_back_and_is_corrected() {
    let f = fixture("cabinet");
    let mut drawer = f.joint("drawer");
    drawer.axis_in_object = [0.0, 1.0, 0.0];
    let reasons = f.failures(&drawer);
    assert!(
        reasons.iter().any(|r| r.contains("passes through")),
        "{reasons:?}"
    );
    let fixed = f.corrected(&drawer);
    let limits = fixed.limits.expect("limits");
    let direction =
        DVec3::from_array(fixed.axis_in_object) * (limits.lower + limits.upper).signum();
    assert!(direction.dot(DVec3::NEG_Y) > 0.99, "{fixed:?}");
}

#[test]
fn a_door_hinged_on_the_wrong_edge_or_axis_fails_and_a_passing_variant_is_found() {
    let f = fixture("cabinet");
    let door = f.joint("door");
    // Hinge on the right edge instead of the left: the door swings through the left panel.
    let mut wrong_pivot = door.clone();
    wrong_pivot.pivot_in_object_m[0] = -wrong_pivot.pivot_in_object_m[0];
    assert!(!f.failures(&wrong_pivot).is_empty());
    assert!(f.failures(&f.corrected(&wrong_pivot)).is_empty());
    // A horizontal axis through the bottom-left corner: the door tips sideways into the panel.
    let mut wrong_axis = door.clone();
    wrong_axis.axis_in_object = [0.0, 1.0, 0.0];
    assert!(!f.failures(&wrong_axis).is_empty());
    assert!(f.failures(&f.corrected(&wrong_axis)).is_empty());
}

#[test]
fn a_hinge_far_from_its_parent_loses_contact() {
    let f = fixture("box_with_lid");
    let mut lid = f.joint("lid");
    let pivot = DVec3::from_array(lid.pivot_in_object_m) + DVec3::new(0.0, 0.0, 0.5);
    lid.pivot_in_object_m = pivot.to_array();
    lid.limits = Some(JointLimits {
        lower: 0.0,
        upper: 1.2,
    });
    let reasons = f.failures(&lid);
    assert!(
        reasons.iter().any(|r| r.contains("lost contact")),
        "{reasons:?}"
    );
}
