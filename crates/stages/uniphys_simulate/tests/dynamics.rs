//! The dynamic check on hand-built assets: sound assets pass, broken ones fail for the right
//! reason, and the collision-filter policy decides what touches.

mod assets;

use assets::TestAsset;
use uniphys_simulate::{DynamicParams, DynamicReport, SimulateError, check_dynamics};
use uniphys_types::{CheckOutcome, JointKind, PartId};

fn check(asset: &TestAsset, excluded: &[(PartId, PartId)]) -> DynamicReport {
    check_dynamics(
        &asset.record,
        &asset.colliders,
        excluded,
        &DynamicParams::default(),
    )
    .expect("check runs")
}

fn outcome(report: &DynamicReport, joint: &str) -> CheckOutcome {
    report
        .joint(joint)
        .expect("joint in report")
        .verdict
        .outcome
}

fn reasons(report: &DynamicReport, joint: &str) -> String {
    report
        .joint(joint)
        .expect("joint in report")
        .verdict
        .reasons
        .join("; ")
}

#[test]
fn closed_lid_stays_shut_and_opens_to_both_limits() {
    let report = check(&assets::box_with_lid(0.05, 0.02), &[]);
    let lid = report.joint("lid_hinge").expect("lid joint");
    assert_eq!(lid.verdict.outcome, CheckOutcome::Pass, "{report:#?}");
    assert!(lid.rest.max_drift < lid.rest.tolerance);
    // Lid 0.4 x 0.3 x 0.02 m of 700 kg/m^3 = 1.68 kg, centre of mass 0.15 m in front of the hinge:
    // gravity pushes it closed, into its lower limit, with 1.68 * 9.81 * 0.15 N m.
    assert!(
        (lid.rest.gravity_load + 1.68 * 9.81 * 0.15).abs() < 1e-9,
        "{}",
        lid.rest.gravity_load
    );
    assert!(lid.drive.times_to_reach_s.iter().all(Option::is_some));
    // Opening 1.9 rad at 1.9 rad/s takes about a second.
    let t_up = lid.drive.times_to_reach_s[1].expect("upper reached");
    assert!((0.9..1.6).contains(&t_up), "{t_up}");
    assert!(lid.drive.energy_gain_after_release_j <= lid.drive.energy_tolerance_j);
}

#[test]
fn open_lid_with_weak_friction_falls_closed_and_only_warns() {
    // Exported open by 0.8 rad; 0.01 N m of friction cannot hold 1.6 N m of gravity.
    let report = check(&assets::box_with_open_lid(0.8, 0.05, 0.01), &[]);
    let lid = report.joint("lid_hinge").expect("lid joint");
    assert_eq!(lid.verdict.outcome, CheckOutcome::Warn, "{report:#?}");
    assert!(
        (lid.rest.final_q + 0.8).abs() < lid.rest.tolerance,
        "{}",
        lid.rest.final_q
    );
    assert!(reasons(&report, "lid_hinge").contains("settles on a limit"));
}

#[test]
fn open_lid_with_strong_friction_stays_open() {
    let report = check(&assets::box_with_open_lid(0.8, 0.05, 5.0), &[]);
    assert_eq!(
        outcome(&report, "lid_hinge"),
        CheckOutcome::Pass,
        "{report:#?}"
    );
    let lid = report.joint("lid_hinge").expect("lid joint");
    assert!(lid.rest.max_drift < 1e-3, "{}", lid.rest.max_drift);
}

#[test]
fn drawer_slides_to_both_limits() {
    let report = check(&assets::drawer_in_carcass(2.0, 0.5), &[]);
    assert_eq!(
        outcome(&report, "drawer_slide"),
        CheckOutcome::Pass,
        "{report:#?}"
    );
    let drawer = report.joint("drawer_slide").expect("drawer joint");
    assert_eq!(drawer.kind, JointKind::Prismatic);
    assert!(drawer.rest.gravity_load.abs() < 1e-9);
    assert!(drawer.drive.target_errors[1] < 0.006, "{:?}", drawer.drive);
}

#[test]
fn a_lid_lifted_a_centimetre_against_gravity_reaches_its_upper_limit() {
    // Driven at 1 cm/s, gravity would take all of that speed from a 1000/s velocity servo.
    let report = check(&assets::pot_with_lifting_lid(0.01), &[]);
    let lid = report.joint("lid_lift").expect("lid joint");
    assert_eq!(lid.verdict.outcome, CheckOutcome::Pass, "{report:#?}");
    assert!(lid.rest.gravity_load < 0.0);
    let t_up = lid.drive.times_to_reach_s[1].expect("upper reached");
    assert!(t_up < 1.5, "{t_up}");
}

#[test]
fn drawer_blocked_by_a_welded_rail_fails_to_reach_its_upper_limit() {
    // The rail sits 0.1 m in front of the drawer, which should slide out 0.3 m.
    let report = check(&assets::drawer_blocked_by_rail(0.1), &[]);
    let drawer = report.joint("drawer_slide").expect("drawer joint");
    assert_eq!(drawer.rest.verdict.outcome, CheckOutcome::Pass);
    assert_eq!(drawer.verdict.outcome, CheckOutcome::Fail, "{report:#?}");
    assert!(drawer.drive.times_to_reach_s[1].is_none());
    // Stopped at the rail: about 0.1 m out, 0.2 m short.
    assert!((drawer.drive.target_errors[1] - 0.2).abs() < 0.01);
    assert!(reasons(&report, "drawer_slide").contains("does not reach the upper target"));
}

#[test]
fn door_on_a_vertical_hinge_feels_no_gravity_and_stays_put() {
    let report = check(&assets::door_cabinet(0.2, 0.05), &[]);
    let door = report.joint("door_hinge").expect("door joint");
    assert_eq!(door.verdict.outcome, CheckOutcome::Pass, "{report:#?}");
    assert!(door.rest.gravity_load.abs() < 1e-12);
    assert!(door.rest.max_drift < 1e-4);
}

#[test]
fn touching_sibling_doors_block_each_other_unless_the_pair_is_excluded() {
    let asset = assets::two_door_cabinet(0.0);
    let blocked = check(&asset, &[]);
    assert_eq!(
        outcome(&blocked, "left_hinge"),
        CheckOutcome::Fail,
        "{blocked:#?}"
    );
    assert_eq!(outcome(&blocked, "right_hinge"), CheckOutcome::Fail);
    let excluded = check(&asset, &[(PartId(1), PartId(2))]);
    assert!(excluded.passed(), "{excluded:#?}");
    for joint in &excluded.joints {
        assert_eq!(joint.verdict.outcome, CheckOutcome::Pass, "{joint:#?}");
    }
}

#[test]
fn welded_bumper_pushing_the_door_open_fails_at_rest_unless_excluded() {
    // The bumper reaches 3 cm into the closed door; the door's friction holds gravity (no load
    // on a vertical hinge), so the motion is a contact push, not physics the asset intends.
    let asset = assets::door_cabinet_with_bumper(0.03);
    let pushed = check(&asset, &[]);
    let door = pushed.joint("door_hinge").expect("door joint");
    assert_eq!(door.rest.verdict.outcome, CheckOutcome::Fail, "{pushed:#?}");
    assert!(door.rest.max_drift > door.rest.tolerance);
    assert!(reasons(&pushed, "door_hinge").contains("holds the gravity load"));
    let excluded = check(&asset, &[(PartId(1), PartId(2))]);
    assert_eq!(
        outcome(&excluded, "door_hinge"),
        CheckOutcome::Pass,
        "{excluded:#?}"
    );
}

#[test]
fn undamped_heavy_lever_swings_and_fails() {
    let report = check(&assets::free_pendulum(), &[]);
    let bar = report.joint("bar_hinge").expect("bar joint");
    assert_eq!(bar.verdict.outcome, CheckOutcome::Fail, "{report:#?}");
    assert!(bar.rest.reversals >= 1);
    assert!(reasons(&report, "bar_hinge").contains("swings"));
}

#[test]
fn the_same_lever_with_heavy_damping_falls_without_swinging_and_only_warns() {
    let mut asset = assets::free_pendulum();
    asset.record.joints[0].damping = 20.0;
    // No armature, so that the damping alone keeps it from swinging.
    let params = DynamicParams {
        armature_s: 0.0,
        ..DynamicParams::default()
    };
    let report = check_dynamics(&asset.record, &asset.colliders, &[], &params).expect("runs");
    let bar = report.joint("bar_hinge").expect("bar joint");
    assert_eq!(bar.rest.verdict.outcome, CheckOutcome::Warn, "{report:#?}");
    assert_eq!(bar.rest.reversals, 0);
    assert!(bar.rest.max_drift > bar.rest.tolerance);
}

#[test]
fn limits_that_exclude_the_rest_pose_fail() {
    let mut asset = assets::box_with_lid(0.05, 0.02);
    let limits = asset.record.joints[0].limits.as_mut().expect("limits");
    limits.lower = 0.8;
    let report = check(&asset, &[]);
    assert_eq!(
        outcome(&report, "lid_hinge"),
        CheckOutcome::Fail,
        "{report:#?}"
    );
    assert!(reasons(&report, "lid_hinge").contains("outside the limits"));
}

#[test]
fn report_section_has_one_check_per_movable_joint_with_its_metrics() {
    // Four movable joints; the rail asset adds a fixed joint that must not appear.
    let report = check(&assets::two_door_cabinet(0.0), &[(PartId(1), PartId(2))]);
    let section = report.to_report_section();
    assert_eq!(section.name, "dynamics");
    let subjects: Vec<&str> = section.checks.iter().map(|c| c.subject.as_str()).collect();
    assert_eq!(
        subjects,
        [
            "joint left_hinge",
            "joint right_hinge",
            "joint drawer_slide",
            "joint knob_turn"
        ]
    );
    assert!(section.passed());
    let metrics = report.metrics();
    assert_eq!(metrics.len(), 4);
    assert!(metrics["joint drawer_slide"].contains_key("rest_max_drift_m"));
    assert!(metrics["joint left_hinge"].contains_key("rest_max_drift_rad"));
    assert!(metrics["joint left_hinge"].contains_key("drive_upper_time_s"));

    let rail = check(&assets::drawer_blocked_by_rail(0.1), &[]);
    let section = rail.to_report_section();
    assert_eq!(section.checks.len(), 1);
    assert_eq!(section.checks[0].outcome, CheckOutcome::Fail);
    assert!(!section.passed());
}

#[test]
fn mismatched_colliders_and_bad_params_are_errors_not_verdicts() {
    let asset = assets::door_cabinet(0.2, 0.05);
    let err = check_dynamics(
        &asset.record,
        &asset.colliders[..1],
        &[],
        &DynamicParams::default(),
    );
    assert!(matches!(
        err,
        Err(SimulateError::ColliderCount {
            parts: 2,
            colliders: 1
        })
    ));
    let params = DynamicParams {
        rest_duration_s: f64::NAN,
        ..DynamicParams::default()
    };
    let err = check_dynamics(&asset.record, &asset.colliders, &[], &params);
    assert!(matches!(err, Err(SimulateError::InvalidParams { .. })));
}

#[test]
fn a_loose_hanging_handle_is_kicked_when_the_drawer_is_driven_and_a_damped_one_is_not() {
    let loose = check(&assets::drawer_with_hanging_handle(0.0, 0.0), &[]);
    let handle = loose.joint("handle_pin").expect("handle joint");
    // At rest it hangs still: no gravity load, so it is judged for kicks.
    assert_eq!(
        handle.rest.verdict.outcome,
        CheckOutcome::Pass,
        "{loose:#?}"
    );
    let drawer = loose.joint("drawer_slide").expect("drawer joint");
    assert_eq!(drawer.verdict.outcome, CheckOutcome::Fail, "{loose:#?}");
    assert_eq!(
        drawer.drive.most_kicked_joint.as_deref(),
        Some("handle_pin")
    );
    assert!(drawer.drive.max_kick_ratio > 1.0);
    assert!(reasons(&loose, "drawer_slide").contains("kicks joint handle_pin"));

    let damped = check(&assets::drawer_with_hanging_handle(0.05, 0.05), &[]);
    let drawer = damped.joint("drawer_slide").expect("drawer joint");
    assert_eq!(drawer.verdict.outcome, CheckOutcome::Pass, "{damped:#?}");
    assert!(drawer.drive.max_kick_ratio < 1.0);
}

#[test]
fn a_heavy_knob_with_almost_no_rotational_inertia_spins_on_its_own() {
    // 50 kg on the knob's axis with an inertia of 1e-9 kg m^2 (the real one is ~1e-5 for 30 g),
    // no damping, no friction: the engine's rounding pushes are no longer negligible against
    // the inertia, and the knob turns to its limit with no gravity load to explain it.
    let mut asset = assets::two_door_cabinet(0.0);
    let knob = &mut asset.record.parts[4].mass;
    knob.inertia_about_com_kg_m2 = [[1e-9, 0.0, 0.0], [0.0, 1e-9, 0.0], [0.0, 0.0, 1e-9]];
    knob.mass_kg.value = 50.0;
    let joint = &mut asset.record.joints[3];
    joint.damping = 0.0;
    joint.friction = 0.0;
    let report = check(&asset, &[(PartId(1), PartId(2))]);
    let knob = report.joint("knob_turn").expect("knob joint");
    assert_eq!(knob.rest.verdict.outcome, CheckOutcome::Fail, "{report:#?}");
    assert!(knob.rest.max_drift > 10.0 * knob.rest.tolerance);
    assert!(reasons(&report, "knob_turn").contains("holds the gravity load"));
    // The doors and the drawer are still fine.
    for name in ["left_hinge", "right_hinge", "drawer_slide"] {
        assert_eq!(outcome(&report, name), CheckOutcome::Pass, "{name}");
    }
}

#[test]
fn a_continuous_knob_is_driven_a_quarter_turn_each_way() {
    let mut asset = assets::two_door_cabinet(0.0);
    let knob = &mut asset.record.joints[3];
    knob.kind = JointKind::Continuous;
    knob.limits = None;
    let report = check(&asset, &[(PartId(1), PartId(2))]);
    let knob = report.joint("knob_turn").expect("knob joint");
    assert_eq!(knob.verdict.outcome, CheckOutcome::Pass, "{report:#?}");
    let quarter = std::f64::consts::FRAC_PI_2;
    assert_eq!(knob.drive.targets, [-quarter, quarter]);
    assert!(
        knob.drive
            .target_errors
            .iter()
            .all(|e| *e <= knob.rest.tolerance)
    );
}
