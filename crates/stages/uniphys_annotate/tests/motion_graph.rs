//! Motion graph rules: one parent per movable part, co-moving groups through D links only,
//! cycles, contradictions and disagreements reported.

use uniphys_annotate::schema::{
    DescriptionsAnswer, MovementType, NeighbourAnswer, PartAnswer, PropertiesAnswer,
};
use uniphys_annotate::{MotionIssueKind, motion_graph};
use uniphys_types::JointKind;

fn touch(label: u32, kind: MovementType) -> NeighbourAnswer {
    NeighbourAnswer {
        label,
        movement_type: kind,
        parent: None,
        child: None,
        damping: None,
        range: None,
    }
}

fn moves(label: u32, kind: MovementType, parent: u32, child: u32, range: &str) -> NeighbourAnswer {
    NeighbourAnswer {
        label,
        movement_type: kind,
        parent: Some(parent),
        child: Some(child),
        damping: Some(0.05),
        range: Some(range.to_owned()),
    }
}

fn answer(neighbours: Vec<Vec<NeighbourAnswer>>) -> PropertiesAnswer {
    PropertiesAnswer {
        object_name: "cabinet".into(),
        category: "Furniture".into(),
        dimensions: "60*40*90 cm".into(),
        mass: "20 kg".into(),
        parts: neighbours
            .into_iter()
            .enumerate()
            .map(|(i, neighbours)| PartAnswer {
                label: u32::try_from(i + 1).expect("small"),
                name: format!("part {}", i + 1),
                material: "wood/oak".into(),
                density: "0.7 g/cm^3".into(),
                youngs_modulus_gpa: 11.0,
                hardness_hv: 7.0,
                poisson_ratio: 0.3,
                friction_coefficient: 0.5,
                affordance_rank: 3,
                graspable: false,
                neighbours,
                descriptions: DescriptionsAnswer::default(),
            })
            .collect(),
    }
}

use MovementType::{A, B, C, D};

#[test]
fn a_cabinet_gives_a_drawer_and_a_door_with_their_handles_but_not_the_shelf() {
    // 1 body, 2 drawer, 3 drawer handle, 4 door, 5 door handle, 6 shelf the drawer rests on.
    let graph = motion_graph(&answer(vec![
        vec![
            moves(2, B, 1, 2, "0-30 cm"),
            moves(4, C, 1, 4, "0-90 degrees"),
            touch(6, D),
        ],
        vec![moves(1, B, 1, 2, "0-30 cm"), touch(3, D), touch(6, A)],
        vec![touch(2, D)],
        vec![moves(1, C, 1, 4, "0-90 degrees"), touch(5, D)],
        vec![touch(4, D)],
        vec![touch(1, D), touch(2, A)],
    ]));
    assert!(graph.issues.is_empty(), "{:?}", graph.issues);
    assert_eq!(graph.movable.len(), 2);
    let drawer = graph.movable_part(2).expect("drawer moves");
    assert_eq!((drawer.parent, drawer.kind), (1, JointKind::Prismatic));
    assert!((drawer.limits.upper - 0.3).abs() < 1e-12 && drawer.limits.lower == 0.0);
    assert_eq!(
        drawer.group,
        vec![2, 3],
        "the touching shelf 6 must not move with the drawer"
    );
    let door = graph.movable_part(4).expect("door turns");
    assert_eq!((door.parent, door.kind), (1, JointKind::Revolute));
    assert!((door.limits.upper - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert_eq!(door.group, vec![4, 5]);
    let fixed: Vec<(u32, u32)> = graph.fixed.iter().map(|f| (f.parent, f.child)).collect();
    assert_eq!(fixed, vec![(2, 3), (4, 5)]);
}

#[test]
fn a_second_parent_is_a_contradiction_and_the_first_is_kept() {
    let graph = motion_graph(&answer(vec![
        vec![moves(3, C, 1, 3, "0-90 degrees")],
        vec![moves(3, C, 2, 3, "0-45 degrees")],
        vec![],
    ]));
    assert_eq!(graph.movable.len(), 1);
    assert_eq!(graph.movable[0].parent, 1);
    assert_eq!(graph.issues.len(), 1);
    assert_eq!(graph.issues[0].kind, MotionIssueKind::TwoParents);
    assert_eq!(graph.issues[0].labels, vec![1, 2, 3]);
}

#[test]
fn a_parent_chain_that_closes_a_cycle_is_refused() {
    let graph = motion_graph(&answer(vec![
        vec![moves(2, C, 1, 2, "0-90 degrees")],
        vec![moves(3, B, 2, 3, "0-10 cm")],
        vec![moves(1, B, 3, 1, "0-10 cm")],
    ]));
    assert_eq!(graph.movable.len(), 2);
    assert!(graph.movable_part(1).is_none());
    assert!(
        graph
            .issues
            .iter()
            .any(|i| i.kind == MotionIssueKind::Cycle && i.labels == vec![1, 3]),
        "{:?}",
        graph.issues
    );
}

#[test]
fn touch_with_a_link_opposite_directions_and_differing_ranges_are_reported() {
    let graph = motion_graph(&answer(vec![
        vec![
            touch(2, A),
            moves(3, C, 1, 3, "0-90 degrees"),
            moves(4, B, 1, 4, "0-20 cm"),
        ],
        vec![touch(1, D)],
        vec![moves(1, C, 3, 1, "0-90 degrees")],
        vec![moves(1, B, 1, 4, "0-25 cm")],
    ]));
    let kinds: Vec<MotionIssueKind> = graph.issues.iter().map(|i| i.kind).collect();
    assert!(
        kinds.contains(&MotionIssueKind::TouchAndLinked),
        "{kinds:?}"
    );
    assert!(kinds.contains(&MotionIssueKind::Contradiction));
    assert!(kinds.contains(&MotionIssueKind::Disagreement));
    assert_eq!(graph.movable_part(3).map(|m| m.parent), Some(1));
    let slide = graph.movable_part(4).expect("slides");
    assert!(
        (slide.limits.upper - 0.20).abs() < 1e-12,
        "the first range is kept"
    );
}

#[test]
fn a_rigid_link_to_the_parent_or_another_group_is_reported_not_followed() {
    // 2 turns on 1; 3 is rigid with both 2 and 1 (contradiction); 5 slides on 1; 4 rigid with 2 and 5.
    let graph = motion_graph(&answer(vec![
        vec![
            moves(2, C, 1, 2, "0-90 degrees"),
            moves(5, B, 1, 5, "0-10 cm"),
        ],
        vec![touch(3, D), touch(4, D)],
        vec![touch(2, D), touch(1, D)],
        vec![touch(2, D), touch(5, D)],
        vec![],
    ]));
    let hinge = graph.movable_part(2).expect("turns");
    assert_eq!(hinge.group, vec![2, 3, 4]);
    let slide = graph.movable_part(5).expect("slides");
    assert_eq!(slide.group, vec![5]);
    let kinds: Vec<MotionIssueKind> = graph.issues.iter().map(|i| i.kind).collect();
    assert!(kinds.contains(&MotionIssueKind::Contradiction), "{kinds:?}");
    assert!(
        kinds.contains(&MotionIssueKind::SharedRigidPart),
        "{kinds:?}"
    );
}

#[test]
fn an_unknown_neighbour_label_is_reported() {
    let graph = motion_graph(&answer(vec![vec![touch(9, D)], vec![]]));
    assert_eq!(graph.issues.len(), 1);
    assert_eq!(graph.issues[0].kind, MotionIssueKind::UnknownLabel);
}
