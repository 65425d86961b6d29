//! The whole raw-mesh path on a real object of the shared PartNet-Mobility set
//! (`../shared/data/partnet-mobility/` beside the repository): the object merged into one bare
//! mesh at rest (no parts, names, colours or joints), run with decomposition and the built-in
//! grounder, its parts paired with the true links by shared surface (`uniphys eval
//! --match-parts overlap`), and its true joints checked through that pairing.
//! `articulation-bench --partnet --decompose` measures the whole set.

use uniphys_decompose::DecomposeOptions;
use uniphys_decompose::output::obj_text;
use uniphys_eval::{
    AnnotatedAsset, PartOverlap, annotated_from_mesh_asset, load_prediction_with_surfaces,
    load_urdf_asset, match_parts_by_overlap, mesh_asset_part_surfaces, renamed_by_overlap,
};
use uniphys_examples::shared_partnet_object;
use uniphys_geometry::{DVec3, TriMesh};
use uniphys_mesh_io::IngestOptions;
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::UpAxis;

#[test]
fn an_oven_merged_into_one_mesh_comes_back_with_its_knobs_turning() {
    // Eight knobs (continuous joints) on an oven's control panel, and a drawer under it.
    assert_spins_come_back("kitchen-101921", 8);
}

#[test]
fn a_cart_merged_into_one_mesh_comes_back_with_its_wheels_spinning() {
    // Four wheels on a cart whose frame the decomposition leaves in pieces: each wheel's
    // parent is the small bracket that holds its axle. A wheel's spokes pass that bracket as it
    // turns, so their contact changes while the wheel, round about its axle, turns in place;
    // judged by that change, the spin failed and was corrected into a slide along the axle.
    assert_spins_come_back("kitchen-101090", 4);
}

#[test]
fn a_table_merged_into_one_mesh_comes_back_with_its_drawers_sliding() {
    // Two drawers side by side under a table top, each with a knob. The decomposition leaves
    // the table in several parts and hangs each drawer from the largest: that part walls a
    // drawer in on one side only, the other drawer and the other boards on the rest. Walled in
    // by its parent alone, a drawer's slide ran in no slot and was corrected into a hinge.
    assert_drawers_slide("kitchen-32932", 2);
}

#[test]
fn a_drawer_hung_from_a_tables_lower_frame_slides_out_under_the_top() {
    // The decomposition hangs the drawer from the table's lower frame and leaves the top another
    // part. Judged against its parent alone, nothing lay above the drawer: it closed the frame's
    // top like a lid, and its way out along that side was ruled out (fixed).
    assert_drawers_slide("gensim2-22241", 1);
}

/// The shared object `name` merged into one bare mesh, run with decomposition and the built-in
/// grounder: its `drawers` true slides come back as slides along their axes.
fn assert_drawers_slide(name: &str, drawers: usize) {
    let (pred, gt, matches) = run_merged(name);
    let slides: Vec<_> = gt.joints.iter().filter(|j| j.motion_type == 'B').collect();
    assert_eq!(slides.len(), drawers, "{:?}", gt.joints);
    for drawer in slides {
        let found = pred.joint_of(&drawer.child).unwrap_or_else(|| {
            panic!(
                "{}: no part found for it\nmatches {matches:#?}",
                drawer.child
            )
        });
        let angle = DVec3::from_array(found.axis)
            .normalize()
            .dot(DVec3::from_array(drawer.axis).normalize())
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        assert!(
            found.motion_type == 'B' && angle < 10.0,
            "{}: {} along an axis {angle:.1} deg off the way it pulls out",
            drawer.child,
            found.motion_type
        );
    }
}

/// The shared object `name` merged into one bare mesh, run with decomposition and the built-in
/// grounder: its `spins` parts that spin without limit come back spinning about their axes.
fn assert_spins_come_back(name: &str, spins: usize) {
    let (pred, gt, matches) = run_merged(name);
    let true_spins: Vec<_> = gt
        .joints
        .iter()
        .filter(|j| j.motion_type == 'C' && j.range == Some([0.0, std::f64::consts::TAU]))
        .collect();
    assert_eq!(true_spins.len(), spins, "{:?}", gt.joints);
    let mut wrong = Vec::new();
    for spin in true_spins {
        let Some(found) = pred.joint_of(&spin.child) else {
            let m = matches.iter().find(|m| m.gt_part == spin.child);
            wrong.push(format!("{}: no part found for it ({m:?})", spin.child));
            continue;
        };
        let angle = DVec3::from_array(found.axis)
            .normalize()
            .dot(DVec3::from_array(spin.axis).normalize())
            .abs()
            .clamp(0.0, 1.0)
            .acos()
            .to_degrees();
        if found.motion_type != 'C' || angle > 10.0 {
            wrong.push(format!(
                "{}: {} about an axis {angle:.1} deg off",
                spin.child, found.motion_type
            ));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}\nmatches {matches:#?}");
}

/// The prediction for the shared object `name` merged into one bare mesh at rest (its parts
/// renamed to the true links they share most surface with), the truth, and the pairing.
fn run_merged(name: &str) -> (AnnotatedAsset, AnnotatedAsset, Vec<PartOverlap>) {
    let urdf = shared_partnet_object(name);
    let truth = load_urdf_asset(&urdf, &IngestOptions::default()).expect("ingest the truth");
    let merged = truth.merged();
    let bare = TriMesh {
        positions: merged.positions,
        triangles: merged.triangles,
        ..TriMesh::default()
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("merged.obj");
    std::fs::write(&input, obj_text(&bare)).expect("write the merged mesh");
    let mut options = RunOptions {
        ingest: IngestOptions {
            up_axis: Some(UpAxis::Z),
            ..IngestOptions::default()
        },
        decompose: Some(DecomposeOptions::default()),
        unit_auto: false,
        ..RunOptions::default()
    };
    options.verify.dynamics = None;
    let output = run(&input, &options, &NoProgress).expect("pipeline runs");
    let out = dir.path().join("out");
    for artifact in output
        .artifacts
        .iter()
        .filter(|a| a.path == "record.json" || a.path.starts_with("parts/"))
    {
        let path = out.join(&artifact.path);
        std::fs::create_dir_all(path.parent().expect("a folder")).expect("mkdir");
        std::fs::write(&path, &artifact.bytes).expect("write an output file");
    }
    let (pred, pred_surfaces) = load_prediction_with_surfaces(&out).expect("the run's parts");
    let gt = annotated_from_mesh_asset(&truth, name);
    let matches = match_parts_by_overlap(
        &pred,
        &pred_surfaces,
        &gt,
        &mesh_asset_part_surfaces(&truth),
    )
    .expect("parts matched");
    (renamed_by_overlap(&pred, &matches), gt, matches)
}
