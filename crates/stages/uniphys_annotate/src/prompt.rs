//! The prompts, written for this project and versioned as files under `prompts/<version>/`
//! (embedded at build time). The version heads every system prompt, so it is part of each
//! request and of its cache key (a prompt change never reuses an old answer), and it is the
//! version in the provenance of every value.

use crate::validate::Violation;

/// Version of the prompt files in use.
pub const PROMPT_VERSION: &str = "v1";
/// Line before the answer's JSON.
pub const BEGIN_MARKER: &str = "===BEGIN_JSON===";
/// Line after the answer's JSON.
pub const END_MARKER: &str = "===END_JSON===";

const PROPERTIES_SYSTEM: &str = include_str!("../prompts/v1/properties_system.txt");
const PROPERTIES_USER: &str = include_str!("../prompts/v1/properties_user.txt");
const ARTICULATION_SYSTEM: &str = include_str!("../prompts/v1/articulation_system.txt");
const ARTICULATION_USER: &str = include_str!("../prompts/v1/articulation_user.txt");

/// A system prompt and a user text, ready for a request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Prompt {
    /// System message.
    pub system: String,
    /// User text (the images follow it).
    pub user_text: String,
}

/// Replaces every `{key}` of `template` by its value, in one pass over the template: text a value
/// brings in (a part description the model wrote, say) is never searched for placeholders.
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let value = after.find('}').and_then(|close| {
            let key = &after[..close];
            values
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| (*v, close))
        });
        match value {
            Some((value, close)) => {
                out.push_str(value);
                rest = &after[close + 1..];
            }
            None => {
                out.push('{');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

fn system(text: &str, purpose: &str) -> String {
    format!("[UniPhys {purpose} prompt {PROMPT_VERSION}]\n{text}")
}

/// The properties request for `part_count` parts. `names` (object name, then one per part), when
/// the input has meaningful names, are offered as hints.
#[must_use]
pub fn properties_prompt(part_count: usize, names: Option<(&str, &[String])>) -> Prompt {
    let naming = match names {
        Some((object, parts)) if parts.len() == part_count => {
            let list: Vec<String> = parts
                .iter()
                .enumerate()
                .map(|(i, n)| format!("label {}: '{n}'", i + 1))
                .collect();
            format!(
                "The input file calls the object '{object}' and its parts {}; these names may be unhelpful, trust the images. ",
                list.join(", ")
            )
        }
        _ => String::new(),
    };
    let count = part_count.to_string();
    Prompt {
        system: system(PROPERTIES_SYSTEM, "properties"),
        user_text: fill(
            PROPERTIES_USER,
            &[("part_count", &count), ("naming", &naming)],
        ),
    }
}

/// What the articulation request says about one moving part.
#[derive(Debug, Clone)]
pub struct ArticulationContext<'a> {
    /// Its label.
    pub label: u32,
    /// Its name from the properties answer.
    pub part_name: &'a str,
    /// The object name from the properties answer.
    pub object_name: &'a str,
    /// Whether it turns (else it slides).
    pub revolute: bool,
    /// Its descriptions from the properties answer.
    pub descriptions: &'a uniphys_types::Descriptions,
    /// Axis legend: colour name and unit vector in the object frame.
    pub axes: Vec<(&'a str, [f64; 3])>,
    /// Pivot legend colour names (revolute only).
    pub pivots: Vec<&'a str>,
}

/// The articulation request of one moving part.
#[must_use]
pub fn articulation_prompt(ctx: &ArticulationContext<'_>) -> Prompt {
    let axis_table: Vec<String> = ctx
        .axes
        .iter()
        .map(|(name, v)| format!(" - {name}: ({:.3}, {:.3}, {:.3})", v[0], v[1], v[2]))
        .collect();
    let pivot_table = if ctx.revolute {
        format!(
            "Candidate pivots: {} (or \"average\" for the centre of all six).\n",
            ctx.pivots.join(", ")
        )
    } else {
        String::new()
    };
    let label = ctx.label.to_string();
    let axis_table = axis_table.join("\n");
    Prompt {
        system: system(ARTICULATION_SYSTEM, "articulation"),
        user_text: fill(
            ARTICULATION_USER,
            &[
                ("label", &label),
                ("part_name", ctx.part_name),
                ("object_name", ctx.object_name),
                (
                    "motion_kind",
                    if ctx.revolute {
                        "REVOLUTE (it turns about an axis)"
                    } else {
                        "PRISMATIC (it slides along an axis)"
                    },
                ),
                ("basic", &ctx.descriptions.basic),
                ("functional", &ctx.descriptions.functional),
                ("movement", &ctx.descriptions.movement),
                ("axis_table", &axis_table),
                ("pivot_table", &pivot_table),
                (
                    "pivot_request",
                    if ctx.revolute {
                        " and the pivot"
                    } else {
                        " (pivot null)"
                    },
                ),
            ],
        ),
    }
}

/// The user text of the repair turn: the original request, the previous answer and every
/// violation, asking for a corrected answer.
#[must_use]
pub fn repair_text(
    original_user_text: &str,
    previous_answer: &str,
    violations: &[Violation],
) -> String {
    let list: Vec<String> = violations.iter().map(|v| format!(" - {v}")).collect();
    let previous: String = previous_answer.chars().take(6000).collect();
    format!(
        "{original_user_text}\n\nYour previous answer was:\n{previous}\n\nIt does not follow the schema:\n{}\nAnswer again with the complete corrected JSON between {BEGIN_MARKER} and {END_MARKER}.",
        list.join("\n")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_are_filled_and_versioned() {
        let p = properties_prompt(3, Some(("box", &["a".into(), "b".into(), "c".into()])));
        assert!(p.system.starts_with("[UniPhys properties prompt v1]"));
        assert!(p.user_text.contains("the 3 parts") && p.user_text.contains("label 2: 'b'"));
        assert!(!p.user_text.contains('{'), "{}", p.user_text);
        let none = properties_prompt(3, Some(("box", &["a".into()])));
        assert!(!none.user_text.contains("label 1:"));
        let d = uniphys_types::Descriptions::default();
        let a = articulation_prompt(&ArticulationContext {
            label: 2,
            part_name: "lid",
            object_name: "box",
            revolute: true,
            descriptions: &d,
            axes: vec![("Dark Gray", [0.0, 0.0, 1.0])],
            pivots: vec!["Red", "Green"],
        });
        assert!(a.user_text.contains(" - Dark Gray: (0.000, 0.000, 1.000)"));
        assert!(a.user_text.contains("Red, Green") && a.user_text.contains("REVOLUTE"));
        assert!(!a.user_text.contains("{axis_table}"));
    }

    #[test]
    fn placeholders_inside_values_are_left_alone() {
        let filled = fill(
            "parts: {parts}; table: {axis_table}; {unknown} {",
            &[("parts", "lid says {axis_table}"), ("axis_table", "T")],
        );
        assert_eq!(
            filled,
            "parts: lid says {axis_table}; table: T; {unknown} {"
        );
    }
}
