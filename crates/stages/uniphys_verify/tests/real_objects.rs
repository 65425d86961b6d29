//! The verifier on real objects of the shared PartNet-Mobility set
//! (`../shared/data/partnet-mobility/` beside the repository): true joints handed over as a
//! grounder's (swept and correctable) pass unchanged, and deliberately broken ones are caught
//! and put back. `scripts/bench` (verify-bench) measures the whole set.

use uniphys_examples::shared_partnet_object;
use uniphys_geometry::{
    Aabb, ConvexParams, DVec3, TriMesh, convex_decomposition, parallel_map, projection_range,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::{CheckOutcome, Joint, JointLimits, Provenance};
use uniphys_verify::{JointVerdict, Scene, SweepParams, verify_joint};

struct Object {
    scene: Scene,
    /// The true joints, with a grounder's provenance (so they may be corrected).
    joints: Vec<Joint>,
}

fn object(name: &str) -> Object {
    let mut loaded =
        load_asset(&shared_partnet_object(name), &IngestOptions::default()).expect("ingest");
    loaded.asset.rest_on_ground();
    let meshes: Vec<TriMesh> = loaded.asset.parts.iter().map(|p| p.mesh.clone()).collect();
    let colliders: Vec<Vec<TriMesh>> = parallel_map(&meshes, |m| {
        convex_decomposition(m, &ConvexParams::default()).expect("hulls")
    });
    let joints = loaded
        .asset
        .joints
        .iter()
        .map(|j| Joint {
            provenance: Provenance::provider("test-truth", "partnet-mobility"),
            ..j.clone()
        })
        .collect();
    Object {
        scene: Scene::new(&meshes, &colliders, 1500).expect("scene"),
        joints,
    }
}

impl Object {
    fn movable(&self) -> Vec<usize> {
        (0..self.joints.len())
            .filter(|&i| self.joints[i].kind.is_movable())
            .collect()
    }

    /// Verifies joint `i` of `joints` (correction on).
    fn verify(&self, joints: &[Joint], i: usize) -> JointVerdict {
        verify_joint(&self.scene, joints, i, &SweepParams::default(), true).expect("verify")
    }

    /// The joints with joint `i` replaced by `broken`.
    fn with(&self, i: usize, broken: Joint) -> Vec<Joint> {
        let mut joints = self.joints.clone();
        joints[i] = broken;
        joints
    }

    /// Joint `i` with its range reversed fails for `reason` and is corrected back to its true
    /// range by a reversal.
    fn assert_reversal_caught_and_undone(&self, i: usize, reason: &str) {
        let truth = &self.joints[i];
        let verdict = self.caught(i, reversed(truth));
        assert!(verdict.message.contains(reason), "{}", verdict.message);
        let (fixed, change) = verdict.correction.expect("corrected");
        assert!(change.contains("reversed"), "{change}");
        assert_eq!(fixed.limits, truth.limits);
    }

    /// Joint `i` turned a quarter ([`sideways`]) fails for `reason` and is corrected back onto
    /// its true line ([`assert_restored_to_true_line`]).
    fn assert_sideways_caught_and_restored(&self, i: usize, reason: &str) {
        let truth = &self.joints[i];
        let verdict = self.caught(i, sideways(truth));
        assert!(verdict.message.contains(reason), "{}", verdict.message);
        assert_restored_to_true_line(&verdict, truth, part_diagonal(self, truth.child.0));
    }

    /// `truth` with its hinge line moved across its part's centre, to the opposite edge.
    fn hinged_on_opposite_edge(&self, truth: &Joint) -> Joint {
        let axis = DVec3::from_array(truth.axis_in_object).normalize();
        let pivot = DVec3::from_array(truth.pivot_in_object_m);
        let part = self.scene.points_of(&[truth.child.0 as usize]);
        let centre = part.iter().sum::<DVec3>() / part.len() as f64;
        Joint {
            pivot_in_object_m: (pivot - 2.0 * (pivot - centre).reject_from_normalized(axis))
                .to_array(),
            ..truth.clone()
        }
    }

    /// Verifies joint `i` with `broken` in its place, which the sweep must fail.
    /// Joint `i` made a slide along its own line (half the part's length along it, as
    /// verify-bench's "revolute made prismatic" does) is caught and corrected back to a joint
    /// of its true kind on its true line ([`assert_restored_to_true_line`]); returns it.
    fn assert_slide_hinged_again(&self, i: usize) -> Joint {
        let truth = &self.joints[i];
        let axis = DVec3::from_array(truth.axis_in_object).normalize();
        let (lo, hi) = projection_range(&self.scene.points_of(&[truth.child.0 as usize]), axis);
        let slide = Joint {
            kind: uniphys_types::JointKind::Prismatic,
            limits: Some(JointLimits {
                lower: 0.0,
                upper: 0.5 * (hi - lo),
            }),
            ..truth.clone()
        };
        let verdict = self.caught(i, slide);
        assert_restored_to_true_line(&verdict, truth, part_diagonal(self, truth.child.0));
        let (fixed, change) = verdict.correction.expect("corrected");
        assert_eq!(fixed.kind, truth.kind, "{change}");
        fixed
    }

    fn caught(&self, i: usize, broken: Joint) -> JointVerdict {
        let verdict = self.verify(&self.with(i, broken), i);
        assert_ne!(verdict.outcome, CheckOutcome::Pass, "{}", verdict.message);
        verdict
    }
}

/// `truth` with its axis turned a quarter ([`quarter_turned`]).
fn sideways(truth: &Joint) -> Joint {
    Joint {
        axis_in_object: quarter_turned(truth.axis_in_object),
        ..truth.clone()
    }
}

/// A correction, if the verdict made one, may only give back the true axis (within 2 degrees).
fn assert_correction_keeps_true_axis(verdict: &JointVerdict, truth: &Joint) {
    if let Some((fixed, _)) = &verdict.correction {
        assert!(
            line_angle_deg(fixed.axis_in_object, truth.axis_in_object) < 2.0,
            "{fixed:?}"
        );
    }
}

/// Angle between two lines, degrees.
fn line_angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (a, b) = (
        DVec3::from_array(a).normalize(),
        DVec3::from_array(b).normalize(),
    );
    a.dot(b).abs().clamp(0.0, 1.0).acos().to_degrees()
}

/// `axis` turned a quarter, towards the object axis least aligned with it.
fn quarter_turned(axis: [f64; 3]) -> [f64; 3] {
    let axis = DVec3::from_array(axis).normalize();
    let least = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .min_by(|a, b| a.dot(axis).abs().total_cmp(&b.dot(axis).abs()))
        .unwrap_or(DVec3::X);
    least.reject_from_normalized(axis).normalize().to_array()
}

fn assert_true_joints_pass_unchanged(name: &str) {
    let o = object(name);
    let movable = o.movable();
    assert!(!movable.is_empty(), "{name} has movable joints");
    for i in movable {
        let verdict = o.verify(&o.joints, i);
        assert_eq!(
            verdict.outcome,
            CheckOutcome::Pass,
            "{name} {}: {}",
            o.joints[i].name,
            verdict.message
        );
        assert!(verdict.correction.is_none());
    }
}

// These true joints were "corrected" (a refrigerator door to an axis about 90 degrees off,
// dishwasher buttons to move outward) or failed (cart wheels turning inside their forks) when
// the sweep measured the interpenetration of convex hulls, which fill the cavities of real parts.
#[test]
fn a_refrigerator_door_passes_unchanged() {
    assert_true_joints_pass_unchanged("kitchen-10905");
}

#[test]
fn dishwasher_buttons_and_door_pass_unchanged() {
    assert_true_joints_pass_unchanged("kitchen-12428");
}

#[test]
fn cart_wheels_turning_in_their_forks_pass_unchanged() {
    assert_true_joints_pass_unchanged("kitchen-100491");
}

// A camera's shutter button is written to travel 5 mm; it meets the bottom of its socket in the
// body 0.3 mm before that. The written limit's overshoot lies in the end stop, so the joint passes
// as written (it was cut to 4.2 mm). Pressed half as far again, it goes through the body: caught,
// and the range this stage writes ends before the body.
const CAMERA: &str = "kitchen-101352";

#[test]
fn camera_buttons_pressed_to_the_bottom_of_their_sockets_pass_unchanged() {
    assert_true_joints_pass_unchanged(CAMERA);
}

#[test]
fn a_button_pressed_half_as_far_again_through_the_body_is_caught_and_cut() {
    let o = object(CAMERA);
    let i = o
        .joints
        .iter()
        .position(|j| j.name == "joint_1")
        .expect("joint_1");
    let truth = o.joints[i].clone();
    let written = truth.limits.expect("limits");
    let mut deeper = truth.clone();
    deeper.limits = Some(JointLimits {
        lower: written.lower,
        upper: written.upper * 1.5,
    });
    let verdict = o.caught(i, deeper);
    assert!(
        verdict.message.contains("passes through part"),
        "{}",
        verdict.message
    );
    let (fixed, change) = verdict.correction.expect("corrected");
    assert!(change.contains("range cut"), "{change}");
    let cut = fixed.limits.expect("limits");
    assert!(cut.upper < written.upper, "{cut:?} against {written:?}");
}

/// The range of `joint` reversed: the part moves the other way.
fn reversed(joint: &Joint) -> Joint {
    let limits = joint.limits.expect("a limited joint");
    Joint {
        limits: Some(JointLimits {
            lower: -limits.upper,
            upper: -limits.lower,
        }),
        ..joint.clone()
    }
}

#[test]
fn a_microwave_door_swinging_inward_is_caught_and_reversed() {
    let o = object("kitchen-7236");
    o.assert_reversal_caught_and_undone(o.movable()[0], "passes through");
}

#[test]
fn a_drawer_pushed_in_or_sliding_sideways_is_caught_and_put_back() {
    let o = object("kitchen-28668");
    let i = o.movable()[0];
    let truth = o.joints[i].clone();
    // Pushed into the table instead of pulled out.
    let verdict = o.caught(i, reversed(&truth));
    let (fixed, _) = verdict.correction.expect("corrected");
    assert_eq!(fixed.limits, truth.limits);
    // Sliding along an axis a quarter turn from the true one: a correction may only give back
    // the drawer's own direction.
    let verdict = o.caught(i, sideways(&truth));
    assert_correction_keeps_true_axis(&verdict, &truth);
}

// These true joints failed before the sweep judged a crossing by its depth across the crossed
// plane and inside its outline, a crossing's depth by the moving part's own size, a hinge's
// overlap by its contact at the hinge line too, and contact thickness for turning joints only.
#[test]
fn table_drawers_sliding_along_flush_legs_and_rails_pass_unchanged() {
    // 26670: the drawer's sides slide flush along the legs' inner faces. 22241: its contact
    // spreads over both side rails and the front frame as it slides.
    assert_true_joints_pass_unchanged("gensim2-26670");
    assert_true_joints_pass_unchanged("gensim2-22241");
}

#[test]
fn bucket_handles_swinging_over_to_the_other_side_pass_unchanged() {
    // Laid against one side of the bucket at rest, against the other at the end.
    assert_true_joints_pass_unchanged("gensim2-100462");
    assert_true_joints_pass_unchanged("gensim2-102365");
}

#[test]
fn a_laptop_screen_closing_onto_its_keyboard_passes_unchanged() {
    assert_true_joints_pass_unchanged("gensim2-10040");
}

// A short slide moves along the normal of the face it sits on, and a hinge is held by its part.
#[test]
fn a_button_slid_across_its_face_is_caught() {
    let o = object("kitchen-12428");
    let buttons: Vec<usize> = o
        .movable()
        .into_iter()
        .filter(|&i| o.joints[i].kind == uniphys_types::JointKind::Prismatic)
        .collect();
    assert!(!buttons.is_empty(), "the dishwasher has buttons");
    for i in buttons {
        let truth = o.joints[i].clone();
        let verdict = o.caught(i, sideways(&truth));
        assert!(
            verdict.message.contains("across the face it sits on"),
            "{}",
            verdict.message
        );
        // A correction may only move it along the face's normal, the true axis.
        assert_correction_keeps_true_axis(&verdict, &truth);
    }
}

// A button set into a face is pressed in; a lid capping its parent lifts off. Either one sent
// the other way crossed nothing (a button pulled out, a lid sunk into its pot's opening) and
// passed before the sweep read which side of its parent the part sits on.
#[test]
fn a_button_pulled_out_of_its_face_is_caught_and_reversed() {
    let o = object("kitchen-101921");
    let button = o
        .movable()
        .into_iter()
        .find(|&i| o.joints[i].kind == uniphys_types::JointKind::Prismatic)
        .expect("the oven has a button");
    o.assert_reversal_caught_and_undone(button, "pulls its part out of the face around it");
}

#[test]
fn a_pot_lid_pushed_into_its_pot_is_caught_and_reversed() {
    let o = object("kitchen-100038");
    o.assert_reversal_caught_and_undone(o.movable()[0], "pushes its part into the parent it caps");
}

// A door turned a quarter about a point of its hinge line swings like a flap along its bottom
// edge, freely and with its handle halfway out: only the handle's bar, which runs along the
// true hinge, tells the two apart.
#[test]
fn a_cabinet_door_hinged_across_its_bar_handle_is_caught_and_hinged_along_it() {
    let o = object("kitchen-46197");
    o.assert_sideways_caught_and_restored(o.movable()[0], "hinged across its handle's bar");
}

// A laptop's screen turned a quarter about a point of its hinge line swings sideways over the
// keyboard, clear of everything: its hinge no longer runs along the base it meets.
#[test]
fn a_laptop_screen_hinged_across_its_hinge_line_is_caught_and_hinged_along_it() {
    let o = object("gensim2-10697");
    let screen = o
        .movable()
        .into_iter()
        .find(|&i| o.joints[i].kind == uniphys_types::JointKind::Revolute)
        .expect("the laptop's screen");
    o.assert_sideways_caught_and_restored(screen, "a panel hinged away from its parent");
}

#[test]
fn a_door_turned_about_a_line_clear_of_it_is_caught() {
    // The true pivot of this cabinet's door lies on its hinge line, 0.84 door heights above the
    // door; turned a quarter, the axis runs across the cabinet above the door.
    let o = object("kitchen-41085");
    let i = o
        .movable()
        .into_iter()
        .find(|&i| o.joints[i].name == "joint_0")
        .expect("joint_0");
    let verdict = o.caught(i, sideways(&o.joints[i]));
    assert!(
        verdict.message.contains("nothing holds it"),
        "{}",
        verdict.message
    );
}

#[test]
fn a_door_hinged_beside_its_handle_is_caught_and_hinged_across_from_it() {
    // The microwave's door handle stands out of its face near the free edge.
    let o = object("kitchen-7167");
    let i = o.movable()[0];
    let truth = o.joints[i].clone();
    let axis = DVec3::from_array(truth.axis_in_object).normalize();
    let pivot = DVec3::from_array(truth.pivot_in_object_m);
    let door = o.scene.points_of(&[truth.child.0 as usize]);
    let verdict = o.caught(i, o.hinged_on_opposite_edge(&truth));
    assert!(
        verdict.message.contains("hinged at its handle"),
        "{}",
        verdict.message
    );
    let (fixed, change) = verdict.correction.expect("corrected");
    assert!(change.contains("pivot moved"), "{change}");
    // Hinged back on the true edge: the new line is nearer the true one than a tenth of the
    // door's reach from it.
    let reach = door
        .iter()
        .map(|p| (*p - pivot).reject_from_normalized(axis).length())
        .fold(0.0, f64::max);
    let off_line = (DVec3::from_array(fixed.pivot_in_object_m) - pivot)
        .reject_from_normalized(axis)
        .length();
    assert!(
        off_line < 0.1 * reach,
        "{off_line} from the true hinge line, reach {reach}"
    );
}

/// The correction of `verdict` turns about the true hinge line of `truth`: its axis within 2
/// degrees and its pivot within 5 % of the moving part's diagonal (`diagonal`) of the line.
fn assert_restored_to_true_line(verdict: &JointVerdict, truth: &Joint, diagonal: f64) {
    let (fixed, change) = verdict.correction.as_ref().expect("corrected");
    assert!(
        line_angle_deg(fixed.axis_in_object, truth.axis_in_object) < 2.0,
        "{change}: {fixed:?}"
    );
    let axis = DVec3::from_array(truth.axis_in_object).normalize();
    let off_line = (DVec3::from_array(fixed.pivot_in_object_m)
        - DVec3::from_array(truth.pivot_in_object_m))
    .reject_from_normalized(axis)
    .length();
    assert!(
        off_line < 0.05 * diagonal,
        "{change}: {off_line} m off the true line"
    );
}

/// The corrected joint's range, read along the true axis (reversed when its axis points the
/// other way), overlaps the true range by more than half of it.
fn assert_range_overlaps_truth(fixed: &Joint, truth: &Joint, context: &str) {
    let way = DVec3::from_array(fixed.axis_in_object).dot(DVec3::from_array(truth.axis_in_object));
    let (f, t) = (fixed.limits.expect("range"), truth.limits.expect("range"));
    let (lo, hi) = if way > 0.0 {
        (f.lower, f.upper)
    } else {
        (-f.upper, -f.lower)
    };
    let overlap = hi.min(t.upper) - lo.max(t.lower);
    assert!(
        overlap > 0.5 * (t.upper - t.lower),
        "{context}: {f:?} against {t:?}"
    );
}

/// Diagonal of the box of part `part`'s samples, metres.
fn part_diagonal(o: &Object, part: u32) -> f64 {
    Aabb::from_points(&o.scene.points_of(&[part as usize])).diagonal()
}

// Several wrong motions can pass a sweep; a correction is chosen by how well it fits the part
// (a hinge along its parent, a handle far from it, a spin about the part's round axis).
#[test]
fn a_laptop_screen_turned_about_its_side_edge_is_hinged_back_along_the_base() {
    // Turned a quarter, the screen swings about its side edge like a door, which the sweep
    // allows; a pivot on that axis passes too. The hinge that runs along the base fits better.
    let o = object("gensim2-11156");
    let i = o.movable()[0];
    let truth = o.joints[i].clone();
    let verdict = o.caught(i, sideways(&truth));
    assert_restored_to_true_line(&verdict, &truth, part_diagonal(&o, truth.child.0));
}

#[test]
fn a_laptop_screen_made_a_slide_is_hinged_again_instead_of_slid_off_its_base() {
    // Slid along its hinge line, the screen runs into the base's hinge blocks. Another slide
    // passes: lifted off the base, held by nothing for most of its travel. A hinge on the same
    // line keeps it on the base and fits, so the turn replaces the slide that left its parent.
    let o = object("gensim2-11156");
    let i = o.movable()[0];
    let truth = o.joints[i].clone();
    let mut slide = truth.clone();
    slide.kind = uniphys_types::JointKind::Prismatic;
    slide.limits = Some(uniphys_types::JointLimits {
        lower: 0.0,
        upper: 0.5 * part_diagonal(&o, truth.child.0),
    });
    let verdict = o.caught(i, slide);
    let (fixed, change) = verdict.correction.clone().expect("corrected");
    assert_eq!(fixed.kind, uniphys_types::JointKind::Revolute, "{change}");
    assert_restored_to_true_line(&verdict, &truth, part_diagonal(&o, truth.child.0));
}

#[test]
fn stove_knobs_turned_about_a_line_across_them_spin_about_their_own_axis_again() {
    let o = object("kitchen-101921");
    let knobs: Vec<usize> = o
        .movable()
        .into_iter()
        .filter(|&i| o.joints[i].kind == uniphys_types::JointKind::Continuous)
        .take(2)
        .collect();
    assert_eq!(knobs.len(), 2, "the stove has knobs");
    for i in knobs {
        o.assert_sideways_caught_and_restored(i, "round about");
    }
}

// A cart's wheel and a microwave's knob on a long stem flipped about a diameter touch nothing
// on their way: the wheel turns in open air under the cart, the knob stands clear of the panel.
// Only their shape tells: each is round about its own axis, not about the flipped one.
#[test]
fn a_wheel_and_a_knob_spun_about_a_diameter_are_caught_and_spun_about_their_axis_again() {
    for name in ["kitchen-100490", "kitchen-7167"] {
        let o = object(name);
        let spins: Vec<usize> = o
            .movable()
            .into_iter()
            .filter(|&i| o.joints[i].kind == uniphys_types::JointKind::Continuous)
            .collect();
        assert!(!spins.is_empty(), "{name} has a part that spins");
        for i in spins {
            o.assert_sideways_caught_and_restored(
                i,
                "spins a round part about a line it is not round about",
            );
        }
    }
}

// A faucet's lever turned a quarter sweeps through the faucet's body. The axes found from the
// lever's box and its contact lean 8 to 13 degrees off the upright it turns about (its grip
// tilts its box); the vertical of an object standing on the ground is tried first.
#[test]
fn faucet_levers_turned_a_quarter_turn_about_the_upright_again() {
    for name in ["gensim2-1556", "gensim2-1053"] {
        let o = object(name);
        let lever = o.movable()[0];
        o.assert_sideways_caught_and_restored(lever, "passes through");
    }
}

// A bucket's handle turned a quarter turn about its attachments: among the new axes, the
// handle's own box axis (the line through both attachments) and a contact axis 9 to 12 degrees
// off it both pass, the tilted one by a slightly smaller misfit. The box axis, listed first and
// fitting nearly as well, is the same hinge given exactly.
#[test]
fn bucket_handles_turned_a_quarter_turn_hinge_on_their_attachments_again() {
    for name in ["gensim2-100435", "gensim2-100462"] {
        let o = object(name);
        o.assert_sideways_caught_and_restored(o.movable()[0], "severe contact overlap change");
    }
}

// A table's drawers hang under its top in a frame open below. Slid sideways into their
// neighbours, they are caught; among the new axes, pulled out toward the front and dropped out of
// the frame both pass and fit alike (slides have no hinge to fit). The drawer pulled out stays on
// its frame all the way; dropped, it leaves it within a few steps.
#[test]
fn drawers_slid_sideways_are_pulled_out_again_not_dropped_out_of_their_frame() {
    let o = object("kitchen-26387");
    let drawers = o.movable();
    for i in [drawers[0], drawers[2]] {
        let truth = o.joints[i].clone();
        let verdict = o.caught(i, sideways(&truth));
        let (fixed, change) = verdict.correction.expect("corrected");
        assert_eq!(fixed.kind, uniphys_types::JointKind::Prismatic, "{change}");
        let same_way =
            DVec3::from_array(fixed.axis_in_object).dot(DVec3::from_array(truth.axis_in_object));
        assert!(same_way > 0.999, "{change}: {fixed:?}");
    }
}

// A cabinet's door made a slide along its hinge line is caught; among the new axes, pulled
// straight off the cabinet's front passed (it lifts off the face it sits on, as a lid does, and
// hits nothing). Only a lift up off a face is held by it: the door is hinged on its line again,
// opening the true way. On kitchen-46197 a slide diagonally across the cabinet's face, held by
// it all the way, passed too; it runs askew of every edge a slide is built along, and the hinge
// fits clearly better. The doors of kitchen-23782 sit inside a frame that walls them in: pulled
// straight out, they passed as drawers, though a door leaves its frame after its own thickness
// (a drawer travels less than its depth).
#[test]
fn cabinet_doors_made_slides_are_hinged_on_their_line_again() {
    for name in [
        "kitchen-41085",
        "kitchen-46166",
        "kitchen-46197",
        "kitchen-23782",
    ] {
        let o = object(name);
        for i in o.movable() {
            let truth = &o.joints[i];
            let fixed = o.assert_slide_hinged_again(i);
            assert_range_overlaps_truth(&fixed, truth, &format!("{name} {i}"));
        }
    }
}

// An oven's doors made slides along their hinge lines: each rests on a ledge, so a slide
// straight up lifts it off that face and was kept as the correction (the door slid up the
// oven's front). A lid lifts off across its own plane; a door moved along its own plane is held
// by nothing but a slot, so the door is hinged on its line again.
#[test]
fn oven_doors_made_slides_are_hinged_again_not_lifted_along_the_front() {
    let o = object("kitchen-101808");
    let all: Vec<usize> = (0..o.scene.part_count()).collect();
    let diagonal = Aabb::from_points(&o.scene.points_of(&all)).diagonal();
    let doors: Vec<usize> = o
        .movable()
        .into_iter()
        .filter(|&i| part_diagonal(&o, o.joints[i].child.0) > 0.3 * diagonal)
        .collect();
    assert_eq!(doors.len(), 2, "the oven's two doors");
    for i in doors {
        o.assert_slide_hinged_again(i);
    }
}

// A drawer hinged about its own slide axis, swung a quarter turn: about a line along its depth
// through its side (where nothing stands below a drawer) it swings down freely. Its carcass walls
// it in across that axis: what sits in a slot slides along it.
#[test]
fn a_drawer_turned_about_its_slide_axis_is_caught_and_slides_again() {
    let o = object("kitchen-28164");
    for i in o.movable() {
        let truth = o.joints[i].clone();
        let part = o.scene.points_of(&[truth.child.0 as usize]);
        let centre = part.iter().sum::<DVec3>() / part.len() as f64;
        let hinged = Joint {
            kind: uniphys_types::JointKind::Revolute,
            pivot_in_object_m: centre.to_array(),
            limits: Some(JointLimits {
                lower: 0.0,
                upper: std::f64::consts::FRAC_PI_2,
            }),
            ..truth.clone()
        };
        let verdict = o.caught(i, hinged);
        let (fixed, change) = verdict.correction.expect("corrected");
        assert_eq!(fixed.kind, uniphys_types::JointKind::Prismatic, "{change}");
        let same_way =
            DVec3::from_array(fixed.axis_in_object).dot(DVec3::from_array(truth.axis_in_object));
        assert!(same_way > 0.999, "{change}: {fixed:?}");
        assert_range_overlaps_truth(&fixed, &truth, &change);
    }
}

// A folding knife's blade hinged about a line in its own plane through its pin: between the
// handle's scales and its spine it sits in a slot. It turns about its normal on the pin.
#[test]
fn a_knife_blade_hinged_along_its_plane_is_caught_and_turned_on_its_pin_again() {
    let o = object("kitchen-102400");
    let blade = o.movable()[0];
    o.assert_sideways_caught_and_restored(blade, "slot");
}

#[test]
fn a_cabinet_door_swung_into_its_hollow_cabinet_is_caught_and_reversed() {
    // The inset door crosses no surface on its way in, but its hull sinks deep into the
    // cabinet's, whose convex pieces fill the cavity.
    let o = object("kitchen-46236");
    let i = o
        .movable()
        .into_iter()
        .find(|&i| o.joints[i].kind == uniphys_types::JointKind::Revolute)
        .expect("a hinged door");
    o.assert_reversal_caught_and_undone(i, "sinks");
}

#[test]
fn a_double_door_hinged_on_its_free_edge_is_hinged_back_on_the_cabinet_side() {
    // Hinged on the edge where the two doors meet, each door swings into the other; swung the
    // other way about that edge it passes, but the line there runs clear of the cabinet (the
    // doors meet in the middle of the opening). The hinge along the cabinet's side fits better.
    let o = object("kitchen-49182");
    let doors = o.movable();
    assert_eq!(doors.len(), 2, "the cabinet has two doors");
    for i in doors {
        let truth = o.joints[i].clone();
        let verdict = o.caught(i, o.hinged_on_opposite_edge(&truth));
        assert_restored_to_true_line(&verdict, &truth, part_diagonal(&o, truth.child.0));
    }
}

#[test]
fn doors_hinged_on_their_handle_edge_are_hinged_back_on_the_far_edge() {
    // Hinged on the edge its handle is on, a cabinet's door swings into the cabinet, sinking
    // into it or rubbing its frame only a little beyond what a true hinge may: it nearly
    // passed. Its
    // reversal passes but leaves the handle beside the hinge (misfit 0.61 and 0.66); a nearly
    // passed joint keeps its axis, and the pivot on the far edge fits clearly better.
    for (name, door) in [("kitchen-23782", 0), ("kitchen-46563", 0)] {
        let o = object(name);
        let i = o.movable()[door];
        let truth = o.joints[i].clone();
        let verdict = o.caught(i, o.hinged_on_opposite_edge(&truth));
        assert_restored_to_true_line(&verdict, &truth, part_diagonal(&o, truth.child.0));
    }
}

// What a sweep alone passes: a panel spun in its own plane over its parent's face, a part
// turned down through the ground the object stands on.
#[test]
fn a_microwave_door_spun_in_its_own_plane_is_caught_and_hinged_back_on_its_edge() {
    // Turned a quarter, the door's axis runs along its own normal: it would slide round over
    // the microwave's front like a clock hand.
    let o = object("kitchen-7236");
    o.assert_sideways_caught_and_restored(o.movable()[0], "like a clock hand");
}

#[test]
fn a_laptop_screen_opened_backwards_through_the_ground_is_caught_and_reversed() {
    let o = object("gensim2-10040");
    o.assert_reversal_caught_and_undone(o.movable()[0], "through the ground");
}
