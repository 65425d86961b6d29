//! Intrinsic verification on a grounded record: the built-in grounder's values pass; values made
//! wrong on purpose fail the level they belong to, with a reason.

use uniphys_examples::{GlbFrame, example, write_glb};
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::{AssetRecord, CheckOutcome};
use uniphys_verify::verify_intrinsic;

fn grounded_box() -> AssetRecord {
    let dir = tempfile::tempdir().expect("tempdir");
    let asset = example("box_with_lid").expect("example");
    let path = dir.path().join("box_with_lid.glb");
    std::fs::write(&path, write_glb(&asset.asset, GlbFrame::YUp).expect("glb")).expect("write");
    run(&path, &RunOptions::default(), &NoProgress)
        .expect("pipeline runs")
        .record
}

/// Failed checks as `(check, message)`.
fn failures(record: &AssetRecord) -> Vec<(String, String)> {
    verify_intrinsic(record)
        .section
        .checks
        .into_iter()
        .filter(|c| c.outcome == CheckOutcome::Fail)
        .map(|c| (c.check, c.message))
        .collect()
}

#[test]
fn grounded_values_pass_every_level() {
    let record = grounded_box();
    let outcome = verify_intrinsic(&record);
    assert!(outcome.section.passed(), "{:?}", failures(&record));
    assert!(outcome.metrics["mass_relative_error"] < 1e-9);
    for level in 0..=4 {
        assert_eq!(outcome.metrics[&format!("level{level}_failures")], 0.0);
    }
}

#[test]
fn a_density_outside_the_wood_prior_fails_level_1_and_the_object_mass_fails_level_4() {
    let mut record = grounded_box();
    // Pine at 100 kg/m^3: below the wood prior (300-900), and the parts' mass sum drops to a
    // fifth of the object's mass.
    for part in &mut record.parts {
        part.properties.density_kg_per_m3.value = 100.0;
    }
    let outcome = verify_intrinsic(&record);
    let failed = failures(&record);
    assert!(
        failed
            .iter()
            .any(|(c, m)| c == "level1_material_prior" && m.contains("density = 100")),
        "{failed:?}"
    );
    assert!(
        failed.iter().any(|(c, _)| c == "level4_object_mass"),
        "{failed:?}"
    );
    let scale = outcome.metrics["volume_scale"];
    let sum: f64 = record
        .parts
        .iter()
        .map(|p| p.properties.density_kg_per_m3.value * p.mass.volume_m3 * scale)
        .sum();
    let expected = (sum - record.object.mass_kg.value).abs() / record.object.mass_kg.value;
    assert!((outcome.metrics["mass_relative_error"] - expected).abs() < 1e-12);
    assert!(expected > 0.5, "{expected}");
}

#[test]
fn hardness_is_checked_against_the_prior_and_against_youngs_modulus() {
    let mut record = grounded_box();
    // Hardness 2e9 Pa: above wood's prior (5e7-5e8) and H/E = 2e9 / E above 0.1 for E below 2e10.
    record.parts[0].properties.hardness_pa.value = 2e9;
    record.parts[0].properties.youngs_modulus_pa.value = 1e10;
    let failed = failures(&record);
    assert!(
        failed
            .iter()
            .any(|(c, m)| c == "level1_material_prior" && m.contains("hardness")),
        "{failed:?}"
    );
    assert!(
        failed
            .iter()
            .any(|(c, m)| c == "level2_hardness_modulus_ratio" && m.contains("2.00e-1")),
        "{failed:?}"
    );
}

#[test]
fn a_slippery_graspable_part_fails_level_3_and_an_impossible_value_level_0() {
    let mut record = grounded_box();
    record.parts[1].properties.graspable.value = true;
    record.parts[1].properties.friction_coefficient.value = 0.1;
    record.parts[0].properties.poisson_ratio.value = 0.7;
    let failed = failures(&record);
    assert!(
        failed
            .iter()
            .any(|(c, m)| c == "level3_interaction_friction" && m.contains("0.1")),
        "{failed:?}"
    );
    assert!(
        failed
            .iter()
            .any(|(c, m)| c == "level0_feasible_values" && m.contains("Poisson")),
        "{failed:?}"
    );
}
