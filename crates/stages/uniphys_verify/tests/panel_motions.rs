//! Motions a sweep alone would pass, judged on plain shapes: a door spun in its own plane over
//! the cabinet's front (like a clock hand), against a folding blade turning between its
//! handle's scales and a round knob turning on its panel; a laptop's screen opened backwards
//! through the ground the laptop stands on, against the same screen closing, and the laptop
//! turned onto a corner, which rests on no ground.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use uniphys_geometry::{ConvexParams, DMat4, DQuat, DVec3, TriMesh, convex_decomposition};
use uniphys_types::{Joint, JointKind, JointLimits, PartId, Provenance};
use uniphys_verify::{Scene, SweepMetrics, SweepParams, edge_pivots, held_pivots, sweep};

fn scene(meshes: Vec<TriMesh>) -> Scene {
    let colliders: Vec<Vec<TriMesh>> = meshes
        .iter()
        .map(|m| convex_decomposition(m, &ConvexParams::default()).expect("hulls"))
        .collect();
    Scene::new(&meshes, &colliders, 1500).expect("scene")
}

/// A revolute joint of part 1 on part 0 about `axis` through `pivot`, over `[lower, upper]`.
fn hinge(axis: [f64; 3], pivot: [f64; 3], lower: f64, upper: f64) -> Joint {
    Joint {
        name: "hinge".to_owned(),
        kind: JointKind::Revolute,
        parent: PartId(0),
        child: PartId(1),
        axis_in_object: axis,
        pivot_in_object_m: pivot,
        limits: Some(JointLimits { lower, upper }),
        damping: 0.0,
        friction: 0.0,
        coupled_parts: Vec::new(),
        provenance: Provenance::rule("test"),
    }
}

fn judge(scene: &Scene, joint: &Joint) -> (SweepMetrics, Vec<String>) {
    let params = SweepParams::default();
    let metrics = sweep(scene, joint, &[1], &params).expect("sweep");
    let reasons = metrics.failures(&params);
    (metrics, reasons)
}

fn spun_in_plane(reasons: &[String]) -> bool {
    reasons.iter().any(|r| r.contains("like a clock hand"))
}

/// A closed cabinet 1 wide (x), 0.6 deep (y), 1.2 tall (z) standing on the ground, and an
/// overlay door 0.03 thick on its front face (y = 0).
fn cabinet() -> Scene {
    scene(vec![
        TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.6, 1.2)),
        TriMesh::cuboid(DVec3::new(0.0, -0.03, 0.0), DVec3::new(1.0, 0.0, 1.2)),
    ])
}

#[test]
fn a_door_spun_in_its_own_plane_over_the_cabinet_front_fails() {
    // About the door's normal through its top left corner, swinging up over the front: the
    // door slides flush along the front and through nothing.
    let scene = cabinet();
    let spun = hinge([0.0, 1.0, 0.0], [0.0, -0.015, 1.2], -FRAC_PI_2, 0.0);
    let (metrics, reasons) = judge(&scene, &spun);
    let turn = metrics
        .in_plane_turn
        .expect("a panel turned about its normal");
    assert!(turn.residual > 0.1, "{turn:?}");
    assert!(turn.sandwiched_share < 0.1, "{turn:?}");
    assert!(spun_in_plane(&reasons), "{reasons:?}");
}

#[test]
fn the_same_door_on_its_edge_hinge_is_no_in_plane_turn() {
    let scene = cabinet();
    let swung = hinge([0.0, 0.0, -1.0], [0.0, -0.03, 0.6], 0.0, FRAC_PI_2);
    let (metrics, reasons) = judge(&scene, &swung);
    assert_eq!(metrics.in_plane_turn, None);
    assert!(reasons.is_empty(), "{reasons:?}");
}

/// A folding knife: a handle 1 long (x) of two scales (part 0, the lower; part 2, the upper)
/// holding the blade (part 1, from `blade_x.0` to `blade_x.1` along the handle) in a gap 0.002
/// wider than the blade.
fn knife(blade_x: (f64, f64)) -> Scene {
    scene(vec![
        TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.1, 0.02)),
        TriMesh::cuboid(
            DVec3::new(blade_x.0, 0.0, 0.021),
            DVec3::new(blade_x.1, 0.1, 0.049),
        ),
        TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.05), DVec3::new(1.0, 0.1, 0.07)),
    ])
}

#[test]
fn a_folding_blade_turning_between_the_scales_of_its_handle_passes() {
    // The blade lies folded in the handle and turns out about the pin near its end.
    let blade = hinge([0.0, 0.0, 1.0], [0.15, 0.05, 0.035], 0.0, PI);
    let (metrics, reasons) = judge(&knife((0.1, 0.9)), &blade);
    let turn = metrics
        .in_plane_turn
        .expect("a panel turned about its normal");
    assert!(turn.residual > 0.1, "{turn:?}");
    assert!(turn.sandwiched_share > 0.9, "{turn:?}");
    assert!(!spun_in_plane(&reasons), "{reasons:?}");
}

#[test]
fn an_open_blade_held_only_at_its_tang_passes() {
    // The blade sticks out of the handle's end; only its tang, around the pin, lies between
    // the scales. What sticks out has nothing over or under it and does not count.
    let blade = hinge([0.0, 0.0, -1.0], [0.9, 0.05, 0.035], 0.0, PI);
    let (metrics, reasons) = judge(&knife((0.8, 1.8)), &blade);
    let turn = metrics
        .in_plane_turn
        .expect("a panel turned about its normal");
    assert!(turn.sandwiched_share > 0.9, "{turn:?}");
    assert!(!spun_in_plane(&reasons), "{reasons:?}");
}

#[test]
fn an_open_blade_is_pivoted_in_the_middle_of_its_held_tang() {
    // The blade (part 1) runs from x = 0.8 to 1.8; the scales hold its tang from 0.8 to 1.0,
    // where the pin runs along z through (0.9, 0.05). The blade's own box lines miss the pin;
    // the region held on both faces is centred on it.
    let scene = knife((0.8, 1.8));
    let to_pin = |p: &DVec3| (*p - DVec3::new(0.9, 0.05, 0.0)).truncate().length();
    let held = held_pivots(&scene, &[1], DVec3::Z, &SweepParams::default());
    let nearest = held.iter().map(to_pin).fold(f64::INFINITY, f64::min);
    assert!(
        nearest < 0.005,
        "held pivots {held:?} miss the pin by {nearest}"
    );
    let blade = scene.points_of(&[1]);
    let boxed = edge_pivots(&blade, &[], [DVec3::X, DVec3::Y, DVec3::Z])
        .iter()
        .map(to_pin)
        .fold(f64::INFINITY, f64::min);
    assert!(boxed > 0.05, "{boxed}");
    // A scale lies on one face of the blade only: nothing holds the scale across both faces.
    assert!(held_pivots(&scene, &[2], DVec3::Z, &SweepParams::default()).is_empty());
}

/// A closed disc of `radius` and `thickness` about the z axis through `centre`'s line, from
/// `centre.z` up, with 48 sides.
fn disc(centre: DVec3, radius: f64, thickness: f64) -> TriMesh {
    const SIDES: u32 = 48;
    let mut positions = vec![centre, centre + DVec3::Z * thickness];
    for k in 0..SIDES {
        let a = TAU * f64::from(k) / f64::from(SIDES);
        let rim = centre + DVec3::new(radius * a.cos(), radius * a.sin(), 0.0);
        positions.push(rim);
        positions.push(rim + DVec3::Z * thickness);
    }
    let mut triangles = Vec::new();
    for k in 0..SIDES {
        let (b0, t0) = (2 + 2 * k, 3 + 2 * k);
        let (b1, t1) = (2 + 2 * ((k + 1) % SIDES), 3 + 2 * ((k + 1) % SIDES));
        triangles.extend([[0, b1, b0], [1, t0, t1], [b0, b1, t1], [b0, t1, t0]]);
    }
    TriMesh::new(positions, triangles).expect("disc")
}

#[test]
fn a_round_knob_turning_on_its_panel_passes() {
    let scene = scene(vec![
        TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.2)),
        disc(DVec3::new(0.5, 0.5, 0.2), 0.1, 0.03),
    ]);
    let knob = hinge([0.0, 0.0, 1.0], [0.5, 0.5, 0.2], 0.0, 1.5 * PI);
    let (metrics, reasons) = judge(&scene, &knob);
    let turn = metrics
        .in_plane_turn
        .expect("a flat disc turned about its normal");
    assert!(turn.residual < 0.05, "{turn:?}");
    assert!(!spun_in_plane(&reasons), "{reasons:?}");
}

/// A laptop standing on the ground: a base 1 wide (x), 0.7 deep (y), 0.04 tall, and an upright
/// screen 0.02 thick standing on its back edge (y from 0.68 to 0.7).
fn laptop() -> Scene {
    scene(vec![
        TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.7, 0.04)),
        TriMesh::cuboid(DVec3::new(0.0, 0.68, 0.04), DVec3::new(1.0, 0.7, 0.74)),
    ])
}

#[test]
fn a_screen_opened_backwards_through_the_ground_fails() {
    // About +x through the hinge at the back edge, positive angles turn the screen's top
    // backwards (+y) and down behind the base, below the ground.
    let (metrics, reasons) = judge(
        &laptop(),
        &hinge([1.0, 0.0, 0.0], [0.0, 0.7, 0.04], 0.0, 2.5),
    );
    assert!(metrics.below_ground_m > 0.3, "{metrics:?}");
    assert!(
        reasons.iter().any(|r| r.contains("through the ground")),
        "{reasons:?}"
    );
}

#[test]
fn the_same_screen_closing_onto_its_base_stays_above_the_ground() {
    let (metrics, reasons) = judge(
        &laptop(),
        &hinge([1.0, 0.0, 0.0], [0.0, 0.7, 0.04], -FRAC_PI_2, 0.0),
    );
    assert!(metrics.below_ground_m < 1e-6, "{metrics:?}");
    assert!(
        !reasons.iter().any(|r| r.contains("through the ground")),
        "{reasons:?}"
    );
}

#[test]
fn a_laptop_turned_onto_a_corner_is_judged_against_no_ground() {
    // The same laptop turned onto a corner of its base touches the plane under it at a point:
    // it does not rest there, so that plane is no ground, and the screen opening backwards
    // is judged by what it passes through alone.
    let turn = DMat4::from_quat(DQuat::from_rotation_y(0.6) * DQuat::from_rotation_x(0.7));
    let upright = [
        TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.7, 0.04)),
        TriMesh::cuboid(DVec3::new(0.0, 0.68, 0.04), DVec3::new(1.0, 0.7, 0.74)),
    ];
    assert!(laptop().ground_z_m.is_some());
    let turned = scene(upright.iter().map(|m| m.transformed(&turn)).collect());
    assert_eq!(turned.ground_z_m, None);
    let axis = turn.transform_vector3(DVec3::X).to_array();
    let pivot = turn.transform_point3(DVec3::new(0.0, 0.7, 0.04)).to_array();
    let (metrics, reasons) = judge(&turned, &hinge(axis, pivot, 0.0, 2.5));
    assert!(metrics.below_ground_m < 1e-9, "{metrics:?}");
    assert!(
        !reasons.iter().any(|r| r.contains("through the ground")),
        "{reasons:?}"
    );
}

/// A strip 1 long (x), 2 cm wide and 2 mm thick lying on a block, along the block's top edge.
fn strip_on_block() -> Scene {
    scene(vec![
        TriMesh::cuboid(DVec3::new(0.0, -0.2, -0.2), DVec3::new(1.0, 0.2, 0.0)),
        TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.02, 0.002)),
    ])
}

#[test]
fn a_thin_strip_hinged_along_its_length_is_a_flap_not_a_round_part_turned_part_way() {
    // A strip 1 long, 2 cm wide and 2 mm thick lying on a block, hinged along its long edge a
    // quarter turn (a sliver a rough decomposition cut off a knife's blade). Turned about that
    // line it stays within its width of itself, a small share of its length: as round, by its
    // diagonal, as a button is. It is a flap: no longer across the line than along it, it is
    // no disc or drum, and the part-way turn rule does not judge it.
    let s = strip_on_block();
    let (metrics, reasons) = judge(&s, &hinge([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0, FRAC_PI_2));
    assert!(metrics.part_way_round_residual.is_none(), "{metrics:?}");
    assert!(
        !reasons.iter().any(|r| r.contains("less than a half turn")),
        "{reasons:?}"
    );
}

#[test]
fn a_thin_strip_spun_about_its_length_is_not_taken_for_a_part_turning_in_place() {
    // The same strip, spun without limit about its long edge: by its diagonal it seems as round
    // about that line as a wheel about its axle, but a flat strip sweeps a disc of its width.
    // Only a disc or a drum turns in place and has its contact's change left unjudged.
    let s = strip_on_block();
    let spin = Joint {
        kind: JointKind::Continuous,
        limits: None,
        ..hinge([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0, 0.0)
    };
    let (metrics, _) = judge(&s, &spin);
    assert!(metrics.spin_round_residual.is_none(), "{metrics:?}");
}
