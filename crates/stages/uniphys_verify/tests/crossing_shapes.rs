//! Crossings on plain shapes: a board sliding flush along a block's face goes through nothing;
//! the same board sliding through the block's middle goes through it.

use uniphys_geometry::{ConvexParams, DVec3, TriMesh, convex_decomposition};
use uniphys_types::{Joint, JointKind, JointLimits, PartId, Provenance};
use uniphys_verify::{Scene, SweepParams, sweep};

/// A floor (part 0), a block standing on it (part 1) and a board standing on it behind the block
/// (part 2), whose face `x = board_face_x` faces the block's side.
fn scene(board_face_x: f64) -> Scene {
    let floor = TriMesh::cuboid(DVec3::new(-1.0, -3.0, -0.1), DVec3::new(2.0, 4.0, 0.0));
    let block = TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.8));
    let board = TriMesh::cuboid(
        DVec3::new(board_face_x - 0.02, -2.0, 0.0),
        DVec3::new(board_face_x, -1.0, 0.6),
    );
    let meshes = vec![floor, block, board];
    let colliders: Vec<Vec<TriMesh>> = meshes
        .iter()
        .map(|m| convex_decomposition(m, &ConvexParams::default()).expect("hulls"))
        .collect();
    Scene::new(&meshes, &colliders, 1500).expect("scene")
}

/// The board slides 3 m along +y over the floor: past the block's whole length.
fn slide() -> Joint {
    Joint {
        name: "board".to_owned(),
        kind: JointKind::Prismatic,
        parent: PartId(0),
        child: PartId(2),
        axis_in_object: [0.0, 1.0, 0.0],
        pivot_in_object_m: [0.0, -1.5, 0.3],
        limits: Some(JointLimits {
            lower: 0.0,
            upper: 3.0,
        }),
        damping: 0.0,
        friction: 0.0,
        coupled_parts: Vec::new(),
        provenance: Provenance::rule("test"),
    }
}

#[test]
fn a_board_sliding_flush_along_a_block_goes_through_nothing() {
    // The board's face lies in the block's side plane x = 0: its samples there meet the edge of
    // the block's back face, slide along its side and leave past its front.
    let params = SweepParams::default();
    let metrics = sweep(&scene(0.0), &slide(), &[2], &params).expect("sweep");
    assert!(metrics.clear_points > 0);
    assert_eq!(metrics.crossed_points, 0, "{metrics:?}");
    // Nothing walls the board in (it runs in no slot, a failure of its own); it crosses nothing.
    let reasons = metrics.failures(&params);
    assert!(
        !reasons.iter().any(|r| r.contains("passes through")),
        "{reasons:?}"
    );
}

#[test]
fn a_board_sliding_through_a_block_passes_through_it() {
    let params = SweepParams::default();
    let metrics = sweep(&scene(0.5), &slide(), &[2], &params).expect("sweep");
    assert_eq!(metrics.crossed_part, Some(1), "{metrics:?}");
    let reasons = metrics.failures(&params);
    assert!(
        reasons.iter().any(|r| r.contains("passes through part 1")),
        "{reasons:?}"
    );
}
