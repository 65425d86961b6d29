use serde_json::{Value, json};
use sha2::{Digest, Sha256};

use crate::{LvlmConfig, LvlmError, LvlmResult};

/// The eight bytes every PNG file starts with.
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];

/// One question to the model: a system prompt, a user text and images (PNG files), in that
/// order in the user message.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ChatRequest {
    /// System prompt.
    pub system: String,
    /// Text part of the user message (first, before the images).
    pub user_text: String,
    /// PNG files, sent as `data:image/png;base64,...` URLs after the text.
    pub images_png: Vec<Vec<u8>>,
    /// What the request is for (e.g. `"properties"`, `"axis"`): for the ledger and error
    /// messages; not sent and not part of the digest.
    pub purpose: String,
}

/// A request as sent: the JSON body and its digest.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RequestBody {
    /// The JSON body of `POST /chat/completions`.
    pub json: String,
    /// SHA-256 (hex) of `json`: the cache key.
    pub digest: String,
}

impl ChatRequest {
    /// A request without images.
    #[must_use]
    pub fn new(
        purpose: impl Into<String>,
        system: impl Into<String>,
        user_text: impl Into<String>,
    ) -> Self {
        Self {
            system: system.into(),
            user_text: user_text.into(),
            images_png: Vec::new(),
            purpose: purpose.into(),
        }
    }

    /// Adds an image (a PNG file) after the text and the images before it.
    #[must_use]
    pub fn with_image(mut self, png: Vec<u8>) -> Self {
        self.images_png.push(png);
        self
    }

    /// The OpenAI chat-completions body for `config`: `model`, `messages` (a system message,
    /// then a user message whose content is a text part followed by one `image_url` part per
    /// image), `reasoning_effort` and `max_completion_tokens` when set. Keys are written in
    /// sorted order, so the same request and options give the same bytes.
    ///
    /// # Errors
    /// [`LvlmError::InvalidRequest`] if an image is not a PNG file.
    pub fn body(&self, config: &LvlmConfig) -> LvlmResult<RequestBody> {
        let mut content = Vec::with_capacity(1 + self.images_png.len());
        content.push(json!({"type": "text", "text": self.user_text}));
        for (index, png) in self.images_png.iter().enumerate() {
            if !png.starts_with(&PNG_SIGNATURE) {
                return Err(LvlmError::InvalidRequest {
                    purpose: self.purpose.clone(),
                    reason: format!(
                        "image {index} ({} bytes) is not a PNG file; encode renders as PNG before sending",
                        png.len()
                    ),
                });
            }
            let url = format!("data:image/png;base64,{}", base64::encode(png));
            content.push(json!({"type": "image_url", "image_url": {"url": url}}));
        }
        let mut body = serde_json::Map::new();
        body.insert("model".to_owned(), Value::String(config.model.clone()));
        body.insert(
            "messages".to_owned(),
            json!([
                {"role": "system", "content": self.system},
                {"role": "user", "content": content},
            ]),
        );
        if let Some(effort) = &config.reasoning_effort {
            body.insert("reasoning_effort".to_owned(), Value::String(effort.clone()));
        }
        if let Some(max) = config.max_completion_tokens {
            body.insert("max_completion_tokens".to_owned(), Value::from(max));
        }
        let json = canonical_json(&Value::Object(body))?;
        let digest = hex::encode(Sha256::digest(json.as_bytes()));
        Ok(RequestBody { json, digest })
    }

    /// SHA-256 (hex) of the canonical body for `config` (model, messages, options; never the
    /// key): the cache key of this request.
    ///
    /// # Errors
    /// As [`ChatRequest::body`].
    pub fn request_digest(&self, config: &LvlmConfig) -> LvlmResult<String> {
        Ok(self.body(config)?.digest)
    }
}

/// JSON with object keys in sorted order at every level, whatever `serde_json`'s map type.
fn canonical_json(value: &Value) -> LvlmResult<String> {
    let sorted = sort_keys(value);
    serde_json::to_string(&sorted).map_err(|source| LvlmError::Encode {
        what: "the chat request",
        source,
    })
}

fn sort_keys(value: &Value) -> Value {
    match value {
        Value::Object(map) => {
            let mut entries: Vec<(&String, &Value)> = map.iter().collect();
            entries.sort_by(|a, b| a.0.cmp(b.0));
            Value::Object(
                entries
                    .into_iter()
                    .map(|(k, v)| (k.clone(), sort_keys(v)))
                    .collect(),
            )
        }
        Value::Array(items) => Value::Array(items.iter().map(sort_keys).collect()),
        other => other.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(marker: u8) -> Vec<u8> {
        let mut bytes = PNG_SIGNATURE.to_vec();
        bytes.extend_from_slice(&[marker; 16]);
        bytes
    }

    #[test]
    fn body_has_the_openai_shape_with_text_then_images() {
        let config = LvlmConfig {
            reasoning_effort: Some("low".to_owned()),
            max_completion_tokens: Some(900),
            ..LvlmConfig::default()
        };
        let request = ChatRequest::new("properties", "sys", "look")
            .with_image(png(1))
            .with_image(png(2));
        let body: Value = serde_json::from_str(&request.body(&config).unwrap().json).unwrap();
        assert_eq!(body["model"], "gpt-5");
        assert_eq!(body["reasoning_effort"], "low");
        assert_eq!(body["max_completion_tokens"], 900);
        assert_eq!(body["messages"][0]["role"], "system");
        assert_eq!(body["messages"][0]["content"], "sys");
        let content = body["messages"][1]["content"].as_array().unwrap();
        assert_eq!(content.len(), 3);
        assert_eq!(content[0], json!({"type": "text", "text": "look"}));
        let url = content[2]["image_url"]["url"].as_str().unwrap();
        let encoded = url.strip_prefix("data:image/png;base64,").unwrap();
        assert_eq!(base64::decode(encoded).unwrap(), png(2));
        assert!(body.get("purpose").is_none());
    }

    #[test]
    fn options_are_left_out_when_unset() {
        let config = LvlmConfig {
            reasoning_effort: None,
            max_completion_tokens: None,
            ..LvlmConfig::default()
        };
        let json = ChatRequest::new("p", "s", "u").body(&config).unwrap().json;
        assert!(!json.contains("reasoning_effort"), "{json}");
        assert!(!json.contains("max_completion_tokens"), "{json}");
    }

    #[test]
    fn digest_depends_on_content_and_options_but_not_key_or_purpose() {
        let config = LvlmConfig::default();
        let request = ChatRequest::new("properties", "s", "u").with_image(png(7));
        let digest = request.request_digest(&config).unwrap();
        assert_eq!(digest.len(), 64);
        let with_key = LvlmConfig {
            api_key: Some("sk-1".to_owned()),
            ..LvlmConfig::default()
        };
        assert_eq!(request.request_digest(&with_key).unwrap(), digest);
        let renamed = ChatRequest {
            purpose: "other".to_owned(),
            ..request.clone()
        };
        assert_eq!(renamed.request_digest(&config).unwrap(), digest);
        let other_model = LvlmConfig {
            model: "qwen2.5-vl".to_owned(),
            ..LvlmConfig::default()
        };
        assert_ne!(request.request_digest(&other_model).unwrap(), digest);
        let other_image = ChatRequest::new("properties", "s", "u").with_image(png(8));
        assert_ne!(other_image.request_digest(&config).unwrap(), digest);
        let no_effort = LvlmConfig {
            reasoning_effort: None,
            ..LvlmConfig::default()
        };
        assert_ne!(request.request_digest(&no_effort).unwrap(), digest);
    }

    #[test]
    fn body_keys_are_sorted() {
        let json = ChatRequest::new("p", "s", "u")
            .body(&LvlmConfig::default())
            .unwrap()
            .json;
        let messages = json.find("\"messages\"").unwrap();
        let model = json.find("\"model\"").unwrap();
        let effort = json.find("\"reasoning_effort\"").unwrap();
        assert!(messages < model && model < effort, "{json}");
    }

    #[test]
    fn a_non_png_image_is_refused_with_its_index() {
        let request = ChatRequest::new("axis", "s", "u")
            .with_image(png(1))
            .with_image(vec![0xff, 0xd8, 0xff]);
        let error = request.body(&LvlmConfig::default()).unwrap_err();
        let message = error.to_string();
        assert!(
            message.contains("image 1") && message.contains("axis"),
            "{message}"
        );
    }
}
