use serde_json::Value;

use crate::{LvlmError, LvlmResult};

/// Token counts of one call, as reported by the server (or estimated when it reported none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct Usage {
    /// Prompt (input) tokens, images included.
    pub prompt_tokens: u64,
    /// Completion (output) tokens, reasoning tokens included.
    pub completion_tokens: u64,
    /// Reasoning tokens, when the server says (part of `completion_tokens`).
    pub reasoning_tokens: Option<u64>,
    /// True when the server sent no `usage` and the counts are the client's estimate.
    #[serde(default)]
    pub estimated: bool,
}

/// The parts of a chat-completions response the client uses.
#[derive(Debug, Clone, PartialEq)]
pub struct ChatResponse {
    /// The answer text (`choices[0].message.content`; text parts joined when it is an array).
    pub text: String,
    /// Token usage, if the server reported it.
    pub usage: Option<Usage>,
    /// The model that answered (the server's `model`, may be empty).
    pub model: String,
    /// `choices[0].finish_reason` (`stop`, `length`, ...), if given.
    pub finish_reason: Option<String>,
}

/// Parses a chat-completions response body.
///
/// # Errors
/// [`LvlmError::Malformed`] saying what is missing (not JSON, an `error` object, no
/// `choices[0]`, no `message.content`, content of another type);
/// [`LvlmError::ModelRefused`] when the message carries a `refusal` and no content.
pub fn parse_chat_response(body: &str) -> LvlmResult<ChatResponse> {
    parse_inner(body).map_err(|failure| match failure {
        Failure::Malformed(what) => LvlmError::Malformed { what },
        Failure::Refused(message) => LvlmError::ModelRefused {
            purpose: "chat".to_owned(),
            message,
        },
    })
}

/// Why a body is not an answer.
pub(crate) enum Failure {
    /// Not a chat completion, or one without content: what is wrong.
    Malformed(String),
    /// The model declined to answer: its refusal text.
    Refused(String),
}

/// Usage found in a body, whatever else is wrong with it (to charge failed attempts).
pub(crate) fn usage_of(body: &str) -> Option<Usage> {
    let value: Value = serde_json::from_str(body).ok()?;
    parse_usage(value.get("usage")?)
}

pub(crate) fn parse_inner(body: &str) -> Result<ChatResponse, Failure> {
    let malformed = |what: String| Failure::Malformed(what);
    let value: Value = serde_json::from_str(body).map_err(|e| {
        malformed(format!(
            "the body is not JSON ({e}); it starts with {:?}",
            crate::error::excerpt(body, 120)
        ))
    })?;
    if let Some(error) = value.get("error").filter(|e| !e.is_null()) {
        return Err(malformed(format!(
            "the body is an error object: {}",
            error_message(error)
        )));
    }
    let choice = value
        .get("choices")
        .and_then(Value::as_array)
        .ok_or_else(|| malformed("no \"choices\" array".to_owned()))?
        .first()
        .ok_or_else(|| malformed("\"choices\" is empty".to_owned()))?;
    let message = choice
        .get("message")
        .ok_or_else(|| malformed("no \"choices[0].message\"".to_owned()))?;
    let text = match message.get("content") {
        Some(Value::String(text)) => text.clone(),
        Some(Value::Array(parts)) => {
            let mut text = String::new();
            for (index, part) in parts.iter().enumerate() {
                match (part.get("type").and_then(Value::as_str), part.get("text")) {
                    (Some("text"), Some(Value::String(piece))) => text.push_str(piece),
                    (Some("text"), _) => {
                        return Err(malformed(format!(
                            "content part {index} is a text part without a \"text\" string"
                        )));
                    }
                    _ => {}
                }
            }
            text
        }
        None | Some(Value::Null) => {
            if let Some(refusal) = message.get("refusal").and_then(Value::as_str) {
                return Err(Failure::Refused(refusal.to_owned()));
            }
            return Err(malformed("no \"choices[0].message.content\"".to_owned()));
        }
        Some(other) => {
            return Err(malformed(format!(
                "\"choices[0].message.content\" is {}, not a string or an array of parts",
                type_name(other)
            )));
        }
    };
    let usage = value.get("usage").and_then(parse_usage);
    Ok(ChatResponse {
        text,
        usage,
        model: value
            .get("model")
            .and_then(Value::as_str)
            .unwrap_or_default()
            .to_owned(),
        finish_reason: choice
            .get("finish_reason")
            .and_then(Value::as_str)
            .map(str::to_owned),
    })
}

fn parse_usage(usage: &Value) -> Option<Usage> {
    let prompt_tokens = usage.get("prompt_tokens")?.as_u64()?;
    let completion_tokens = usage.get("completion_tokens")?.as_u64()?;
    let reasoning_tokens = usage
        .get("completion_tokens_details")
        .and_then(|d| d.get("reasoning_tokens"))
        .and_then(Value::as_u64);
    Some(Usage {
        prompt_tokens,
        completion_tokens,
        reasoning_tokens,
        estimated: false,
    })
}

/// The message of an OpenAI error object (`{"message": ...}`) or the object itself.
pub(crate) fn error_message(error: &Value) -> String {
    match error {
        Value::String(text) => crate::error::excerpt(text, 300),
        _ => error.get("message").and_then(Value::as_str).map_or_else(
            || crate::error::excerpt(&error.to_string(), 300),
            |m| crate::error::excerpt(m, 300),
        ),
    }
}

/// The server's message in an error body: `error.message` if it is an OpenAI error object,
/// else the start of the body.
pub(crate) fn server_message(body: &str) -> String {
    match serde_json::from_str::<Value>(body) {
        Ok(value) => match value.get("error") {
            Some(error) => error_message(error),
            None => crate::error::excerpt(body, 300),
        },
        Err(_) if body.trim().is_empty() => "(empty body)".to_owned(),
        Err(_) => crate::error::excerpt(body, 300),
    }
}

fn type_name(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn string_content_usage_model_and_finish_reason() {
        let body = r#"{"model":"gpt-5-2025","choices":[{"index":0,"finish_reason":"stop",
            "message":{"role":"assistant","content":"hello"}}],
            "usage":{"prompt_tokens":1000,"completion_tokens":200,
            "completion_tokens_details":{"reasoning_tokens":150}}}"#;
        let response = parse_chat_response(body).unwrap();
        assert_eq!(response.text, "hello");
        assert_eq!(response.model, "gpt-5-2025");
        assert_eq!(response.finish_reason.as_deref(), Some("stop"));
        let usage = response.usage.unwrap();
        assert_eq!((usage.prompt_tokens, usage.completion_tokens), (1000, 200));
        assert_eq!(usage.reasoning_tokens, Some(150));
        assert!(!usage.estimated);
    }

    #[test]
    fn array_content_joins_the_text_parts() {
        let body = r#"{"choices":[{"message":{"content":[
            {"type":"text","text":"ab"},{"type":"image_url","image_url":{"url":"x"}},
            {"type":"text","text":"cd"}]}}]}"#;
        let response = parse_chat_response(body).unwrap();
        assert_eq!(response.text, "abcd");
        assert_eq!(response.usage, None);
        assert_eq!(response.model, "");
    }

    #[test]
    fn missing_pieces_are_named() {
        let cases = [
            ("{}", "no \"choices\""),
            (r#"{"choices":[]}"#, "empty"),
            (r#"{"choices":[{}]}"#, "choices[0].message"),
            (
                r#"{"choices":[{"message":{"role":"assistant"}}]}"#,
                "message.content",
            ),
            (r#"{"choices":[{"message":{"content":5}}]}"#, "a number"),
            ("{\"choices\":[{\"mess", "not JSON"),
            (r#"{"error":{"message":"overloaded"}}"#, "overloaded"),
        ];
        for (body, expected) in cases {
            let error = parse_chat_response(body).unwrap_err();
            assert!(matches!(error, LvlmError::Malformed { .. }), "{error}");
            assert!(error.to_string().contains(expected), "{body}: {error}");
        }
    }

    #[test]
    fn a_refusal_is_reported_as_such() {
        let body = r#"{"choices":[{"message":{"content":null,"refusal":"I can't help"}}]}"#;
        let error = parse_chat_response(body).unwrap_err();
        assert!(matches!(error, LvlmError::ModelRefused { .. }), "{error}");
        assert!(error.to_string().contains("I can't help"));
    }

    #[test]
    fn server_messages_come_from_openai_error_objects() {
        assert_eq!(
            server_message(r#"{"error":{"message":"bad model","type":"invalid_request_error"}}"#),
            "bad model"
        );
        assert_eq!(server_message("plain text"), "plain text");
        assert_eq!(server_message(""), "(empty body)");
    }

    #[test]
    fn usage_is_found_even_without_content() {
        let body = r#"{"choices":[],"usage":{"prompt_tokens":5,"completion_tokens":6}}"#;
        let usage = usage_of(body).unwrap();
        assert_eq!((usage.prompt_tokens, usage.completion_tokens), (5, 6));
    }
}
