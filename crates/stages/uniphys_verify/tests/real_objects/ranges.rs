//! Joints moved the wrong way or too far (a range reversed or overshooting) are caught and
//! their range put back.

use uniphys_types::JointLimits;

use crate::support::{CAMERA, object};

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
    let (fixed, change) = o.corrected(i, deeper, "passes through part");
    assert!(change.contains("range cut"), "{change}");
    let cut = fixed.limits.expect("limits");
    assert!(cut.upper < written.upper, "{cut:?} against {written:?}");
}

#[test]
fn a_microwave_door_swinging_inward_is_caught_and_reversed() {
    let o = object("kitchen-7236");
    o.assert_reversal_caught_and_undone(o.movable()[0], "passes through");
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

// An oven's lower door, inset in its frame and hinged at its foot, fits its hollow oven when
// swung inward: it crosses nothing and its hull sinks little into the oven's. Its pull then goes
// into the door's face first, and a handle is pulled.
#[test]
fn an_oven_door_swung_into_the_oven_away_from_its_handle_is_caught_and_reversed() {
    let o = object("kitchen-101808");
    let lower_door = o
        .movable_of(uniphys_types::JointKind::Revolute)
        .into_iter()
        .min_by(|&a, &b| {
            o.joints[a].pivot_in_object_m[2].total_cmp(&o.joints[b].pivot_in_object_m[2])
        })
        .expect("a hinged door");
    o.assert_reversal_caught_and_undone(lower_door, "opens away from its handle");
}

#[test]
fn a_laptop_screen_opened_backwards_through_the_ground_is_caught_and_reversed() {
    let o = object("gensim2-10040");
    o.assert_reversal_caught_and_undone(o.movable()[0], "through the ground");
}

// A screen that only closes from rest, sent the other way, opens backwards until it meets the
// ground late in its range. Cutting it there passes too, but runs the wrong way: the reversal,
// which runs the whole range, fits better and is chosen.
#[test]
fn a_laptop_screen_opened_backwards_until_the_ground_is_reversed_rather_than_cut() {
    let o = object("gensim2-11156");
    o.assert_reversal_caught_and_undone(o.movable()[0], "through the ground");
}
