//! Real size and mass for inputs without a unit: a PartNet-Mobility folder is scaled to the
//! typical size of the kind its `meta.json` names, a file drawn in millimetres is read as such,
//! and open or zero-thickness parts weigh as walls of their material, not as solid blocks.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use uniphys_pipeline::{NoProgress, RunOptions, RunOutput, run};
use uniphys_types::{AssetRecord, CheckOutcome, Provenance, VerificationReport};

/// An OBJ with the given vertices and triangles (1-based indices as OBJ has them).
fn obj(vertices: &[[f64; 3]], faces: &[[usize; 3]]) -> String {
    let mut text = String::new();
    for v in vertices {
        writeln!(text, "v {} {} {}", v[0], v[1], v[2]).expect("a String takes writes");
    }
    for f in faces {
        writeln!(text, "f {} {} {}", f[0], f[1], f[2]).expect("a String takes writes");
    }
    text
}

/// The eight corners of the box [0, size] (index i + 1 in OBJ numbering: bit 0 x, 1 y, 2 z).
fn corners(size: [f64; 3]) -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| {
            [
                if i & 1 == 1 { size[0] } else { 0.0 },
                if i & 2 == 2 { size[1] } else { 0.0 },
                if i & 4 == 4 { size[2] } else { 0.0 },
            ]
        })
        .collect()
}

/// Outward triangles of the box faces: bottom, top, y = 0 (front), y = max (back), x = 0, x = max.
const BOX_FACES: [[[usize; 3]; 2]; 6] = [
    [[1, 3, 4], [1, 4, 2]],
    [[5, 6, 8], [5, 8, 7]],
    [[1, 2, 6], [1, 6, 5]],
    [[3, 7, 8], [3, 8, 4]],
    [[1, 5, 7], [1, 7, 3]],
    [[2, 4, 8], [2, 8, 6]],
];

/// A refrigerator as a PartNet-Mobility folder in normalised units: a body 0.8 x 0.7 x 1.4 open
/// at the front (y = 0) and a door that is one quad drawn on both sides, hinged on its left edge.
fn fridge_folder(root: &Path, meta: Option<&str>) -> PathBuf {
    let folder = root.join("10373");
    let meshes = folder.join("textured_objs");
    std::fs::create_dir_all(&meshes).expect("mesh folder");
    let body_faces: Vec<[usize; 3]> = BOX_FACES
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != 2)
        .flat_map(|(_, f)| *f)
        .collect();
    std::fs::write(
        meshes.join("body.obj"),
        obj(&corners([0.8, 0.7, 1.4]), &body_faces),
    )
    .expect("fixture written");
    let door = [
        [0.0, -0.005, 0.0],
        [0.8, -0.005, 0.0],
        [0.8, -0.005, 1.4],
        [0.0, -0.005, 1.4],
    ];
    std::fs::write(
        meshes.join("door.obj"),
        obj(&door, &[[1, 2, 3], [1, 3, 4], [1, 3, 2], [1, 4, 3]]),
    )
    .expect("fixture written");
    let urdf = r#"<?xml version="1.0"?>
<robot name="10373">
  <link name="base"/>
  <link name="link_0">
    <visual><geometry><mesh filename="textured_objs/door.obj"/></geometry></visual>
  </link>
  <link name="link_1">
    <visual><geometry><mesh filename="textured_objs/body.obj"/></geometry></visual>
  </link>
  <joint name="joint_0" type="revolute">
    <origin xyz="0 -0.005 0"/>
    <axis xyz="0 0 -1"/>
    <parent link="link_1"/>
    <child link="link_0"/>
    <limit lower="0" upper="1.57"/>
  </joint>
  <joint name="joint_1" type="fixed">
    <parent link="base"/>
    <child link="link_1"/>
  </joint>
</robot>
"#;
    std::fs::write(folder.join("mobility.urdf"), urdf).expect("urdf written");
    if let Some(meta) = meta {
        std::fs::write(folder.join("meta.json"), meta).expect("meta.json written");
    }
    folder
}

fn run_with(path: &Path, unit_auto: bool) -> RunOutput {
    let options = RunOptions {
        unit_auto,
        ..RunOptions::default()
    };
    run(path, &options, &NoProgress).expect("pipeline runs")
}

fn largest_side_m(record: &AssetRecord) -> f64 {
    record
        .object
        .dimensions_m
        .value
        .iter()
        .copied()
        .fold(0.0, f64::max)
}

fn plausibility(report: &VerificationReport) -> Vec<(CheckOutcome, String)> {
    report
        .sections
        .iter()
        .flat_map(|s| &s.checks)
        .filter(|c| c.check == "plausibility")
        .map(|c| (c.outcome, c.message.clone()))
        .collect()
}

fn notes(output: &RunOutput) -> String {
    String::from_utf8_lossy(
        &output
            .artifacts
            .iter()
            .find(|a| a.path == "report.json")
            .expect("report.json")
            .bytes,
    )
    .into_owned()
}

#[test]
fn a_partnet_folder_takes_the_size_of_the_kind_its_meta_json_names_and_weighs_like_one() {
    let dir = tempfile::tempdir().expect("tempdir");
    let folder = fridge_folder(dir.path(), Some(r#"{"model_cat": "Refrigerator"}"#));
    let output = run_with(&folder, true);
    let record = &output.record;
    assert!(
        (largest_side_m(record) - 1.75).abs() < 1e-6,
        "{:?}",
        record.object.dimensions_m.value
    );
    assert_eq!(record.object.name.value, "refrigerator");
    assert_eq!(
        record.object.category.value,
        "KitchenDining/KitchenAppliance"
    );
    assert!((record.source.metres_per_unit - 1.75 / 1.4).abs() < 1e-6);
    assert!(notes(&output).contains("unit auto"), "{}", notes(&output));
    // Sheet steel walls: tens of kilograms, where filled solids would weigh tonnes.
    let mass = record.object.mass_kg.value;
    assert!((27.0..240.0).contains(&mass), "{mass} kg");
    for part in &record.parts {
        assert!(
            part.mass.volume_method.starts_with("shell_"),
            "{}: {}",
            part.name,
            part.mass.volume_method
        );
        assert_eq!(part.properties.material.value.subtype, "steel");
    }
    // The walls' thickness is calibrated by the kind's typical mass: every part's method names
    // the same factor.
    let factor: f64 = record.parts[0]
        .mass
        .volume_method
        .rsplit_once("_x")
        .and_then(|(_, f)| f.parse().ok())
        .expect("a calibration factor");
    // The zero-thickness door: its area once (drawn on both sides) times the steel wall.
    let door = record
        .parts
        .iter()
        .find(|p| p.name == "link_0")
        .expect("the door part");
    let area_m2 = 0.8 * 1.4 * (1.75 / 1.4_f64).powi(2);
    assert!(
        (door.mass.volume_m3 / factor / (area_m2 * 0.0008) - 1.0).abs() < 0.01,
        "{} m^3",
        door.mass.volume_m3
    );
    // The walls' own estimate and the kind's typical 80 kg meet halfway, in log space; density
    // times volume is each part's mass, and the parts' masses sum to the object's.
    let parts_kg: f64 = record
        .parts
        .iter()
        .map(|p| {
            let kg = p.mass.volume_m3 * p.properties.density_kg_per_m3.value;
            assert!((kg - p.mass.mass_kg.value).abs() < 1e-9 * kg, "{}", p.name);
            kg
        })
        .sum();
    assert!((parts_kg - mass).abs() < 1e-9 * mass);
    let own_kg = mass / factor;
    assert!(
        (mass / (own_kg * 80.0).sqrt() - 1.0).abs() < 1e-3,
        "{mass} kg from {own_kg} kg"
    );
    assert!(record.parts.iter().all(|p| p.mass.mass_kg.provenance
        == Provenance::rule(
            "density_times_surface_area_times_wall_thickness_calibrated_to_kind_mass"
        )));
    assert!(
        notes(&output).contains("geometric mean"),
        "{}",
        notes(&output)
    );
    let checks = plausibility(&output.report);
    assert_eq!(checks.len(), 2, "mass and size judged: {checks:?}");
    assert!(
        checks.iter().all(|(o, _)| *o == CheckOutcome::Pass),
        "{checks:?}"
    );
}

#[test]
fn a_unit_given_by_the_user_wins_and_an_unknown_kind_keeps_the_coordinates_as_metres() {
    let dir = tempfile::tempdir().expect("tempdir");
    let folder = fridge_folder(dir.path(), Some(r#"{"model_cat": "Refrigerator"}"#));
    let given = run_with(&folder, false);
    assert!((largest_side_m(&given.record) - 1.4).abs() < 1e-6);
    assert!(!notes(&given).contains("unit auto"));

    let dir = tempfile::tempdir().expect("tempdir");
    let folder = fridge_folder(dir.path(), None);
    let unknown = run_with(&folder, true);
    assert!((largest_side_m(&unknown.record) - 1.4).abs() < 1e-6);
    assert!(
        notes(&unknown).contains("1 unit was taken as 1 m"),
        "{}",
        notes(&unknown)
    );
    assert!(plausibility(&unknown.report).is_empty(), "no kind, no band");
}

#[test]
fn a_mug_drawn_in_millimetres_is_read_in_millimetres_and_is_plausible() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("mug.obj");
    // OBJ is Y up: 80 x 95 x 80 units, 95 tall.
    let faces: Vec<[usize; 3]> = BOX_FACES.iter().flat_map(|f| *f).collect();
    std::fs::write(&path, obj(&corners([80.0, 95.0, 80.0]), &faces)).expect("obj written");
    let output = run_with(&path, true);
    let record = &output.record;
    assert!(
        (largest_side_m(record) - 0.095).abs() < 1e-9,
        "{:?}",
        record.object.dimensions_m.value
    );
    assert!(notes(&output).contains("read in mm"), "{}", notes(&output));
    let checks = plausibility(&output.report);
    assert!(
        !checks.is_empty() && checks.iter().all(|(o, _)| *o == CheckOutcome::Pass),
        "{checks:?}"
    );
}

#[test]
fn an_implausible_asset_gets_a_warning_that_says_why() {
    let dir = tempfile::tempdir().expect("tempdir");
    let folder = fridge_folder(dir.path(), Some(r#"{"model_cat": "Refrigerator"}"#));
    let mut record = run_with(&folder, true).record;
    record.object.mass_kg.value = 2000.0;
    let warned: Vec<String> = uniphys_verify::plausibility_checks(&record)
        .into_iter()
        .filter(|c| c.outcome == CheckOutcome::Warn)
        .map(|c| c.message)
        .collect();
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(warned[0].contains("refrigerator") && warned[0].contains("outside the band"));
}
