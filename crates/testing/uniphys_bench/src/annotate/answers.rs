//! The benchmark's model: valid answers generated from the request, so every request gets one
//! answer after the fixed delay.

use serde_json::{Value, json};
use uniphys_annotate::schema::{
    DescriptionsAnswer, MovementType, NeighbourAnswer, PartAnswer, PropertiesAnswer,
};

use crate::synthetic::has_drawer;

fn neighbour(label: u32, kind: MovementType, child: u32, range: &str) -> NeighbourAnswer {
    let moving = kind == MovementType::B || kind == MovementType::C;
    NeighbourAnswer {
        label,
        movement_type: kind,
        parent: moving.then_some(1),
        child: moving.then_some(child),
        damping: moving.then_some(0.05),
        range: moving.then(|| range.to_owned()),
    }
}

/// The properties answer for asset `index` of `parts` parts.
pub(crate) fn properties(index: usize, parts: usize) -> PropertiesAnswer {
    let drawer = has_drawer(index);
    let parts: Vec<PartAnswer> = (1..=parts)
        .map(|label| {
            let label = u32::try_from(label).unwrap_or(u32::MAX);
            let neighbours = match label {
                1 => vec![neighbour(2, MovementType::C, 2, "0-100 degrees")],
                2 => vec![neighbour(1, MovementType::C, 2, "0-100 degrees")],
                3 if drawer => vec![neighbour(1, MovementType::B, 3, "0-30 cm")],
                _ => vec![neighbour(1, MovementType::D, label, "")],
            };
            PartAnswer {
                label,
                name: format!("part {label}"),
                material: "wood/oak".into(),
                density: "0.7 g/cm^3".into(),
                youngs_modulus_gpa: 11.0,
                hardness_hv: 7.0,
                poisson_ratio: 0.3,
                friction_coefficient: 0.5,
                affordance_rank: 3,
                graspable: label != 1,
                neighbours,
                descriptions: DescriptionsAnswer {
                    basic: "a box".into(),
                    functional: "storage".into(),
                    movement: "see neighbours".into(),
                    grasp: String::new(),
                },
            }
        })
        .collect();
    PropertiesAnswer {
        object_name: format!("bench cabinet {index}"),
        category: "Furniture/StorageFurniture".into(),
        dimensions: "80*50*60 cm".into(),
        mass: "20 kg".into(),
        parts,
    }
}

/// The answer text for a request body: properties (asset index and part count read from the
/// user text) or articulation (revolute or prismatic read from the motion type).
pub(crate) fn answer_text(body: &str) -> String {
    let value: Value = if body.contains("UniPhys properties prompt") {
        let index = between(body, "calls the object 'bench_", "'")
            .and_then(|s| s.parse::<usize>().ok())
            .unwrap_or(0);
        let parts = between(body, "Annotate the ", " parts")
            .and_then(|s| s.parse::<usize>().ok())
            .unwrap_or(1);
        serde_json::to_value(properties(index, parts)).unwrap_or(Value::Null)
    } else {
        let revolute = body.contains("Motion type: REVOLUTE");
        json!({
            "part_description": "moving part", "axis_description": "along X",
            "axis_colour": "Red", "motion_direction": "positive",
            "pivot": if revolute { json!("average") } else { Value::Null },
            "justification": "benchmark"
        })
    };
    format!("===BEGIN_JSON===\n{value}\n===END_JSON===")
}

fn between<'a>(text: &'a str, start: &str, end: &str) -> Option<&'a str> {
    let from = text.find(start)? + start.len();
    let len = text[from..].find(end)?;
    Some(&text[from..from + len])
}

/// A chat-completions body with a usage typical of the requests.
pub(crate) fn completion(text: &str) -> Value {
    json!({
        "id": "chatcmpl-bench", "object": "chat.completion", "model": "bench-model",
        "choices": [{"index": 0, "finish_reason": "stop",
                     "message": {"role": "assistant", "content": text}}],
        "usage": {"prompt_tokens": 3000, "completion_tokens": 800, "total_tokens": 3800}
    })
}
