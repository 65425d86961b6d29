//! True joints handed over as a grounder's (swept and correctable) pass unchanged.

use crate::support::{CAMERA, assert_true_joints_pass_unchanged};

// These true joints were "corrected" (a refrigerator door to an axis about 90 degrees off,
// dishwasher buttons to move outward) or failed (cart wheels turning inside their forks) when
// the sweep measured the interpenetration of convex hulls, which fill the cavities of real parts.
#[test]
fn a_refrigerator_door_passes_unchanged() {
    assert_true_joints_pass_unchanged("kitchen-10905");
}

#[test]
fn a_laptop_screen_closing_onto_its_keyboard_passes_unchanged() {
    assert_true_joints_pass_unchanged("gensim2-10040");
}

#[test]
fn dishwasher_buttons_and_door_pass_unchanged() {
    assert_true_joints_pass_unchanged("kitchen-12428");
}

#[test]
fn cart_wheels_turning_in_their_forks_pass_unchanged() {
    assert_true_joints_pass_unchanged("kitchen-100491");
}

#[test]
fn camera_buttons_pressed_to_the_bottom_of_their_sockets_pass_unchanged() {
    assert_true_joints_pass_unchanged(CAMERA);
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
