//! Turning joints about the wrong line (axis turned, pivot moved, a hinge beside its handle, a
//! knob spun about a diameter) are caught and turned about the true line again.

use uniphys_geometry::{DVec3, projection_range};
use uniphys_types::{Joint, JointKind, JointLimits};

use crate::support::{CAMERA, assert_restored_to_true_line, object, part_diagonal, sideways};

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
    let (fixed, change) = o.corrected(i, o.hinged_on_opposite_edge(&truth), "hinged at its handle");
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

// A bucket's handle is held at its two ends, where its line runs through the handle and the
// bucket's rim; between them the line crosses the bucket's opening, far from its walls. Moved
// across the handle or made a slide, the handle is hinged again through its ends, not along a
// line beside the bucket's wall that runs closer to the wall but through no part of the handle.
#[test]
fn bucket_handles_moved_off_their_ends_hinge_on_their_attachments_again() {
    for name in ["gensim2-102358", "gensim2-102367"] {
        let o = object(name);
        let i = o.movable()[0];
        let truth = o.joints[i].clone();
        let verdict = o.caught(i, o.hinged_on_opposite_edge(&truth));
        assert_restored_to_true_line(&verdict, &truth, part_diagonal(&o, truth.child.0));
        o.assert_slide_hinged_again(i);
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

// A laptop's screen spun about its own normal: its foot sits between the base's hinge blocks,
// so about half of the screen's samples near a still surface have one on both faces. Only a
// panel in a slot, held on both faces nearly wherever it is held (a knife's blade between its
// scales), turns so.
#[test]
fn a_laptop_screen_spun_in_its_own_plane_between_its_hinge_blocks_is_caught() {
    let o = object("gensim2-10040");
    let screen = o.movable_of(uniphys_types::JointKind::Revolute)[0];
    o.assert_sideways_caught_and_restored(screen, "like a clock hand");
}

// A stove's round knobs spin without limit (true joints). Made revolute joints a quarter turn,
// each lands on itself and moves nothing: caught, and spun about the same line again. The sweep
// would also let each be pushed a few millimetres into the panel; what keeps a knob turning is
// its shape (its outline is round only up to a grip: a hand can turn it).
#[test]
fn stove_knobs_turned_only_a_quarter_are_caught_and_spun_about_the_same_line() {
    let o = object("kitchen-101921");
    let knobs = o.movable_of(JointKind::Continuous);
    assert!(knobs.len() >= 2, "the stove has knobs");
    for i in knobs {
        let pivot = DVec3::from_array(o.joints[i].pivot_in_object_m);
        o.assert_part_way_round_turn_spun(i, pivot);
    }
}

// A dishwasher's round push buttons, each turned a quarter turn about the line it is pushed
// along through its centre (as verify-bench's "prismatic made revolute" does): turned, a round
// button lands on itself, so nothing collides and the sweep alone passed it. Caught, and not
// flipped about its rim: kept on the same line and pressed into the dishwasher, since each is
// small, squat and smooth all round on the panel's face (a hand has nothing to turn it by, the
// grounder's reading of a button).
#[test]
fn round_buttons_turned_part_way_about_their_line_are_caught_and_pressed_along_it() {
    let o = object("kitchen-12428");
    let buttons = o.movable_of(JointKind::Prismatic);
    assert_eq!(buttons.len(), 4, "the dishwasher has four buttons");
    for i in buttons {
        let part = o.scene.points_of(&[o.joints[i].child.0 as usize]);
        let centre = part.iter().sum::<DVec3>() / part.len() as f64;
        o.assert_part_way_round_turn_pressed(i, centre);
    }
}

// A camera's round buttons drawn as a single flat surface (no depth along their axis), each
// turned a quarter turn about its own line: pressed into the body by a tenth of the button's
// width, as the grounder presses a flat button, not written as a slide of zero length.
#[test]
fn flat_round_buttons_turned_part_way_are_pressed_by_a_stroke_of_their_own() {
    let o = object(CAMERA);
    let flat: Vec<usize> = o
        .movable_of(JointKind::Prismatic)
        .into_iter()
        .filter(|&i| {
            let part = o.scene.points_of(&[o.joints[i].child.0 as usize]);
            let (lo, hi) = projection_range(&part, DVec3::from_array(o.joints[i].axis_in_object));
            hi - lo < 1e-6
        })
        .collect();
    assert!(flat.len() >= 2, "the camera has flat buttons");
    for i in flat {
        let part = o.scene.points_of(&[o.joints[i].child.0 as usize]);
        let centre = part.iter().sum::<DVec3>() / part.len() as f64;
        let verdict = o.caught(
            i,
            Joint {
                kind: JointKind::Revolute,
                pivot_in_object_m: centre.to_array(),
                limits: Some(JointLimits {
                    lower: 0.0,
                    upper: std::f64::consts::FRAC_PI_2,
                }),
                ..o.joints[i].clone()
            },
        );
        let (fixed, change) = verdict.correction.expect("corrected");
        assert_eq!(fixed.kind, JointKind::Prismatic, "{change}");
        let range = fixed.limits.expect("range");
        let stroke = range.upper - range.lower;
        let diagonal = part_diagonal(&o, o.joints[i].child.0);
        assert!(stroke > 0.01 * diagonal, "{change}: a stroke of {stroke} m");
        // Into the body, the way the true joint goes.
        let travel = if range.upper > -range.lower {
            range.upper
        } else {
            range.lower
        };
        let truth = o.joints[i].limits.expect("range");
        assert!(
            travel * truth.upper > 0.0,
            "{change}: pressed the other way"
        );
    }
}
