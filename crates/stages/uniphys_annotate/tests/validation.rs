//! Schema validation: every violation kind is found, with its path, and all of them at once.

use serde_json::{Value, json};
use uniphys_annotate::schema::{MotionDirection, MovementType};
use uniphys_annotate::{Violation, validate_articulation, validate_properties};

fn part(label: u32, neighbours: Value) -> Value {
    json!({
        "label": label, "name": format!("part {label}"), "material": "wood/oak",
        "density": "0.7 g/cm^3", "youngs_modulus_gpa": 11.0, "hardness_hv": 7.0,
        "poisson_ratio": 0.3, "friction_coefficient": 0.5, "affordance_rank": 3,
        "graspable": false, "neighbours": neighbours,
        "descriptions": {"basic": "b", "functional": "f", "movement": "m", "grasp": ""}
    })
}

fn valid() -> Value {
    json!({
        "object_name": "box", "category": "Containers/Box", "dimensions": "30*20*16 cm",
        "mass": "1.5 kg",
        "parts": [
            part(1, json!([{"label": 2, "movement_type": "C", "parent": 1, "child": 2,
                            "damping": 0.05, "range": "0-110 degrees"}])),
            part(2, json!([{"label": 1, "movement_type": "C", "parent": 1, "child": 2,
                            "damping": 0.05, "range": "0-110 degrees"},
                           {"label": 3, "movement_type": "D"}])),
            part(3, json!([{"label": 2, "movement_type": "D"}])),
        ]
    })
}

fn violations(value: &Value) -> Vec<Violation> {
    validate_properties(value, 3).expect_err("invalid")
}

fn has(v: &[Violation], path: &str, fragment: &str) -> bool {
    v.iter()
        .any(|x| x.path == path && x.message.contains(fragment))
}

#[test]
fn a_valid_answer_passes_and_keeps_its_values() {
    let answer = validate_properties(&valid(), 3).expect("valid");
    assert_eq!(answer.parts.len(), 3);
    assert_eq!(answer.parts[1].neighbours[0].movement_type, MovementType::C);
    assert_eq!(
        answer.parts[1].neighbours[0].range.as_deref(),
        Some("0-110 degrees")
    );
    assert_eq!(answer.parts[2].neighbours[0].parent, None);
}

#[test]
fn every_violation_is_reported_with_its_path_at_once() {
    let mut v = valid();
    v["parts"][0]["density"] = json!("7.8 kg");
    v["parts"][0]["material"] = json!("unobtainium/x");
    v["parts"][0]["poisson_ratio"] = json!(0.7);
    v["parts"][1]["friction_coefficient"] = json!(2.5);
    v["parts"][1]["affordance_rank"] = json!(11);
    v["parts"][1]["youngs_modulus_gpa"] = json!("11 GPa");
    v["parts"][2]["hardness_hv"] = json!(-1.0);
    v["parts"][2]["graspable"] = json!("yes");
    v["dimensions"] = json!("30*20 cm");
    v["mass"] = json!("1.5 pounds");
    let found = violations(&v);
    assert!(
        has(&found, "parts[0].density", "\"7.8 kg\" is not in g/cm^3"),
        "{found:?}"
    );
    assert!(has(&found, "parts[0].material", "category of the table"));
    assert!(has(&found, "parts[0].poisson_ratio", "outside"));
    assert!(has(&found, "parts[1].friction_coefficient", "outside"));
    assert!(has(&found, "parts[1].affordance_rank", "outside [1, 10]"));
    assert!(has(&found, "parts[1].youngs_modulus_gpa", "not a number"));
    assert!(has(&found, "parts[2].hardness_hv", "outside"));
    assert!(has(&found, "parts[2].graspable", "not true or false"));
    assert!(has(&found, "dimensions", "L*W*H cm"));
    assert!(has(&found, "mass", "not in kg"));
    assert_eq!(found.len(), 10, "{found:#?}");
    assert_eq!(
        found[0].to_string().split(": ").next(),
        Some(found[0].path.as_str())
    );
}

#[test]
fn labels_must_cover_one_to_n_exactly_once() {
    let mut v = valid();
    v["parts"][2]["label"] = json!(2);
    let found = violations(&v);
    assert!(has(&found, "parts", "label 2 appears 2 times"), "{found:?}");
    assert!(has(&found, "parts", "label 3 is missing"));
    let mut v = valid();
    v["parts"][2]["label"] = json!(4);
    assert!(has(&violations(&v), "parts[2].label", "outside [1, 3]"));
    let mut v = valid();
    v["parts"].as_array_mut().expect("array").pop();
    assert!(has(&violations(&v), "parts", "has 2 entries"));
}

#[test]
fn neighbours_need_existing_labels_and_complete_motion_entries() {
    let mut v = valid();
    v["parts"][2]["neighbours"] = json!([{"label": 7, "movement_type": "D"}]);
    v["parts"][0]["neighbours"] = json!([{"label": 2, "movement_type": "C", "parent": 1, "child": 2,
                                          "damping": 0.05}]);
    v["parts"][1]["neighbours"][0]["movement_type"] = json!("E");
    let found = violations(&v);
    assert!(
        has(&found, "parts[2].neighbours[0].label", "outside [1, 3]"),
        "{found:?}"
    );
    assert!(has(&found, "parts[0].neighbours[0].range", "is missing"));
    assert!(has(
        &found,
        "parts[1].neighbours[0].movement_type",
        "not one of A, B, C, D"
    ));
}

#[test]
fn motion_ranges_need_the_unit_of_their_kind_and_the_right_pair() {
    let mut v = valid();
    v["parts"][0]["neighbours"][0]["range"] = json!("0-30 cm");
    v["parts"][1]["neighbours"][0]["range"] = json!("110-0 degrees");
    v["parts"][2]["neighbours"] = json!([{"label": 1, "movement_type": "B", "parent": 1,
        "child": 2, "damping": 0.1, "range": "0-30 inches"}]);
    let found = violations(&v);
    assert!(
        has(&found, "parts[0].neighbours[0].range", "is a length"),
        "{found:?}"
    );
    assert!(has(
        &found,
        "parts[1].neighbours[0].range",
        "lower to a higher"
    ));
    assert!(has(
        &found,
        "parts[2].neighbours[0]",
        "must be the pair 3 and 1"
    ));
    assert!(has(&found, "parts[2].neighbours[0].range", "is not in"));
}

#[test]
fn an_answer_that_is_not_an_object_is_one_violation() {
    let found = validate_properties(&json!([1, 2]), 3).expect_err("invalid");
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].path, "$");
}

const AXES: [&str; 10] = [
    "Yellow",
    "Orange",
    "Purple",
    "Cyan",
    "Magenta",
    "Dark Gray",
    "Brown",
    "Red",
    "Green",
    "Blue",
];
const PIVOTS: [&str; 6] = ["Red", "Green", "Blue", "Yellow", "Purple", "Brown"];

#[test]
fn articulation_answers_are_checked_against_the_legends() {
    let good =
        json!({"axis_colour": "dark gray", "motion_direction": "Negative", "pivot": "average"});
    let a = validate_articulation(&good, true, &AXES, &PIVOTS).expect("valid");
    assert_eq!(a.motion_direction, MotionDirection::Negative);
    assert_eq!(a.pivot.as_deref(), Some("average"));
    let bad = json!({"axis_colour": "Teal", "motion_direction": "forward", "pivot": "Pink"});
    let found = validate_articulation(&bad, true, &AXES, &PIVOTS).expect_err("invalid");
    assert!(
        has(&found, "axis_colour", "not a colour of the legend"),
        "{found:?}"
    );
    assert!(has(
        &found,
        "motion_direction",
        "not \"positive\" or \"negative\""
    ));
    assert!(has(&found, "pivot", "neither \"average\""));
    let missing_pivot = json!({"axis_colour": "Red", "motion_direction": "positive"});
    assert!(has(
        &validate_articulation(&missing_pivot, true, &AXES, &PIVOTS).expect_err("invalid"),
        "pivot",
        "is missing"
    ));
    let slide = validate_articulation(&missing_pivot, false, &AXES, &PIVOTS).expect("valid");
    assert_eq!(slide.pivot, None);
}
