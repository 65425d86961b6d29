use serde_json::Value;

use crate::error::{excerpt, tail_excerpt};
use crate::{LvlmError, LvlmResult};

/// Marker before the JSON of an answer.
pub const BEGIN_JSON_MARKER: &str = "===BEGIN_JSON===";
/// Marker after the JSON of an answer.
pub const END_JSON_MARKER: &str = "===END_JSON===";

/// How many `{`/`[` positions are tried when looking for JSON outside the markers.
const OUTSIDE_JSON_TRIES: usize = 64;

/// The JSON value between [`BEGIN_JSON_MARKER`] and [`END_JSON_MARKER`] in a model's answer.
///
/// Every marked block is tried in order and the first that parses wins (a model may quote the
/// markers in its prose before the real block); a Markdown code fence around the JSON inside the
/// markers is accepted.
///
/// # Errors
/// - [`LvlmError::NoJsonMarkers`] without a begin marker, saying whether there is JSON outside
///   the markers;
/// - [`LvlmError::UnterminatedJson`] when the last begin marker is never closed and no earlier
///   block parsed (the answer was probably cut off);
/// - [`LvlmError::InvalidJson`] with the parser's message and position (of the last block).
pub fn extract_marked_json(text: &str) -> LvlmResult<Value> {
    let mut rest = text;
    let mut last_error = None;
    while let Some(begin) = rest.find(BEGIN_JSON_MARKER) {
        let after_begin = &rest[begin + BEGIN_JSON_MARKER.len()..];
        let Some(end) = after_begin.find(END_JSON_MARKER) else {
            return Err(LvlmError::UnterminatedJson {
                excerpt: tail_excerpt(text, 120),
            });
        };
        let inside = strip_code_fence(after_begin[..end].trim());
        match serde_json::from_str::<Value>(inside) {
            Ok(value) => return Ok(value),
            Err(error) => {
                last_error = Some(LvlmError::InvalidJson {
                    message: error.to_string(),
                    line: error.line(),
                    column: error.column(),
                    excerpt: excerpt(inside, 120),
                });
            }
        }
        rest = &after_begin[end + END_JSON_MARKER.len()..];
    }
    match last_error {
        Some(error) => Err(error),
        None => Err(LvlmError::NoJsonMarkers {
            json_outside_markers: contains_json_value(text),
            excerpt: excerpt(text, 120),
        }),
    }
}

/// The text inside a Markdown code fence (```` ```json ... ``` ````), or `text` unchanged.
fn strip_code_fence(text: &str) -> &str {
    let Some(opened) = text.strip_prefix("```") else {
        return text;
    };
    let Some(closed) = opened.trim_end().strip_suffix("```") else {
        return text;
    };
    // Drop the info string (`json`) on the fence's first line.
    match closed.find('\n') {
        Some(newline) => closed[newline + 1..].trim(),
        None => closed.trim(),
    }
}

/// Whether an object or array starts somewhere in `text`.
fn contains_json_value(text: &str) -> bool {
    text.char_indices()
        .filter(|(_, c)| *c == '{' || *c == '[')
        .take(OUTSIDE_JSON_TRIES)
        .any(|(index, _)| {
            serde_json::Deserializer::from_str(&text[index..])
                .into_iter::<Value>()
                .next()
                .is_some_and(|parsed| parsed.is_ok())
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use serde_json::json;

    #[test]
    fn the_marked_json_is_returned() {
        let text = "Reasoning...\n===BEGIN_JSON===\n{\"a\": [1, 2]}\n===END_JSON===\nbye";
        assert_eq!(extract_marked_json(text).unwrap(), json!({"a": [1, 2]}));
    }

    #[test]
    fn a_code_fence_inside_the_markers_is_accepted() {
        let text = "===BEGIN_JSON===\n```json\n{\"a\": 1}\n```\n===END_JSON===";
        assert_eq!(extract_marked_json(text).unwrap(), json!({"a": 1}));
    }

    #[test]
    fn markers_quoted_in_prose_before_the_block_are_skipped() {
        let text = "I will answer between ===BEGIN_JSON=== and ===END_JSON===.\n\
                    ===BEGIN_JSON===[true]===END_JSON===";
        assert_eq!(extract_marked_json(text).unwrap(), json!([true]));
    }

    #[test]
    fn json_outside_the_markers_is_reported_as_such() {
        let error = extract_marked_json("Here you go: {\"object_name\": \"mug\"}").unwrap_err();
        assert!(
            matches!(
                error,
                LvlmError::NoJsonMarkers {
                    json_outside_markers: true,
                    ..
                }
            ),
            "{error}"
        );
        assert!(
            error.to_string().contains("JSON outside the markers"),
            "{error}"
        );
    }

    #[test]
    fn no_json_at_all_is_a_different_message() {
        let error = extract_marked_json("I cannot see the image {sorry").unwrap_err();
        assert!(
            matches!(
                error,
                LvlmError::NoJsonMarkers {
                    json_outside_markers: false,
                    ..
                }
            ),
            "{error}"
        );
        assert!(error.to_string().contains("no JSON at all"), "{error}");
    }

    #[test]
    fn an_unclosed_block_is_unterminated() {
        let error =
            extract_marked_json("===BEGIN_JSON===\n{\"parts\": [{\"label\": 1").unwrap_err();
        assert!(
            matches!(error, LvlmError::UnterminatedJson { .. }),
            "{error}"
        );
        assert!(
            error.to_string().contains("max_completion_tokens"),
            "{error}"
        );
    }

    #[test]
    fn invalid_json_carries_the_position() {
        let error = extract_marked_json("===BEGIN_JSON===\n{\"a\": 1,\n \"b\": }\n===END_JSON===")
            .unwrap_err();
        let LvlmError::InvalidJson { line, column, .. } = &error else {
            panic!("{error}");
        };
        assert_eq!((*line, *column), (2, 7));
        assert!(error.to_string().contains("line 2, column 7"), "{error}");
    }

    proptest! {
        #[test]
        fn any_marked_value_round_trips(
            numbers in proptest::collection::vec(-1000i64..1000, 0..8),
            prefix in "[a-z .]{0,40}",
            suffix in "[a-z .]{0,40}",
        ) {
            let value = json!({"numbers": numbers, "name": prefix});
            let text = format!("{prefix}{BEGIN_JSON_MARKER}{value}{END_JSON_MARKER}{suffix}");
            prop_assert_eq!(extract_marked_json(&text).unwrap(), value);
        }
    }
}
