use serde_json::Value;

/// The server's own message in an error body: a JSON `error` (a string or an object with a
/// `message`), `detail` or `message` field, else the start of the body (`(empty body)` when
/// there is none).
#[must_use]
pub fn server_message(body: &str) -> String {
    if let Ok(value) = serde_json::from_str::<Value>(body) {
        for key in ["error", "detail", "message"] {
            match value.get(key) {
                Some(Value::String(text)) => return excerpt(text, 300),
                Some(Value::Object(inner)) => {
                    if let Some(Value::String(text)) = inner.get("message") {
                        return excerpt(text, 300);
                    }
                }
                _ => {}
            }
        }
    }
    if body.trim().is_empty() {
        "(empty body)".to_owned()
    } else {
        excerpt(body, 300)
    }
}

/// The first `max_chars` characters of `text`, with `...` when cut.
#[must_use]
pub fn excerpt(text: &str, max_chars: usize) -> String {
    let mut chars = text.chars();
    let head: String = chars.by_ref().take(max_chars).collect();
    if chars.next().is_some() {
        format!("{head}...")
    } else {
        head
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn server_messages_are_found_in_common_shapes() {
        assert_eq!(server_message(r#"{"error":"bad image"}"#), "bad image");
        assert_eq!(
            server_message(r#"{"error":{"message":"too big","code":1}}"#),
            "too big"
        );
        assert_eq!(server_message(r#"{"detail":"nope"}"#), "nope");
        assert_eq!(server_message("plain text"), "plain text");
        assert_eq!(server_message("  "), "(empty body)");
        assert!(server_message(&"x".repeat(1000)).ends_with("..."));
    }

    #[test]
    fn excerpts_cut_on_characters() {
        assert_eq!(excerpt("héllo", 2), "hé...");
        assert_eq!(excerpt("hé", 2), "hé");
    }
}
