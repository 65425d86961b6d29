use crate::{StorageError, StorageResult};

/// Settings of an S3-compatible store (AWS S3, MinIO, moto). Ignored for local and in-memory stores.
///
/// The library never reads the environment itself: a binary builds this value, for example with
/// [`StorageOptions::from_env_map`]`(std::env::vars())`.
#[derive(Clone, Default, PartialEq, Eq)]
pub struct StorageOptions {
    /// Endpoint URL, e.g. `http://127.0.0.1:9000` for MinIO; `None` means AWS S3 itself.
    pub endpoint: Option<String>,
    /// Region; `None` means `us-east-1` (what MinIO and moto expect by default).
    pub region: Option<String>,
    /// Access key id; without keys `object_store` falls back to instance metadata credentials.
    pub access_key_id: Option<String>,
    /// Secret access key.
    pub secret_access_key: Option<String>,
    /// Session token of temporary credentials.
    pub session_token: Option<String>,
    /// Allow plain `http://` endpoints (local MinIO or moto); off by default.
    pub allow_http: bool,
    /// Virtual-hosted-style requests (`bucket.endpoint/key`) instead of path style
    /// (`endpoint/bucket/key`). Path style is the default because MinIO and moto expect it.
    pub virtual_hosted_style: bool,
}

impl StorageOptions {
    /// Options from `(name, value)` pairs, normally `std::env::vars()`, using the usual AWS names:
    /// `AWS_ENDPOINT_URL` (or `AWS_ENDPOINT`), `AWS_REGION` (or `AWS_DEFAULT_REGION`),
    /// `AWS_ACCESS_KEY_ID`, `AWS_SECRET_ACCESS_KEY`, `AWS_SESSION_TOKEN`, `AWS_ALLOW_HTTP` and
    /// `AWS_VIRTUAL_HOSTED_STYLE_REQUEST` (booleans: `true`/`false`/`1`/`0`). Other names are ignored.
    pub fn from_env_map<I, K, V>(vars: I) -> StorageResult<Self>
    where
        I: IntoIterator<Item = (K, V)>,
        K: AsRef<str>,
        V: Into<String>,
    {
        let mut options = Self::default();
        let mut endpoint_fallback = None;
        let mut region_fallback = None;
        for (name, value) in vars {
            let name = name.as_ref();
            match name {
                "AWS_ENDPOINT_URL" => options.endpoint = Some(value.into()),
                "AWS_ENDPOINT" => endpoint_fallback = Some(value.into()),
                "AWS_REGION" => options.region = Some(value.into()),
                "AWS_DEFAULT_REGION" => region_fallback = Some(value.into()),
                "AWS_ACCESS_KEY_ID" => options.access_key_id = Some(value.into()),
                "AWS_SECRET_ACCESS_KEY" => options.secret_access_key = Some(value.into()),
                "AWS_SESSION_TOKEN" => options.session_token = Some(value.into()),
                "AWS_ALLOW_HTTP" => options.allow_http = parse_bool(name, value.into())?,
                "AWS_VIRTUAL_HOSTED_STYLE_REQUEST" => {
                    options.virtual_hosted_style = parse_bool(name, value.into())?;
                }
                _ => {}
            }
        }
        options.endpoint = options.endpoint.or(endpoint_fallback);
        options.region = options.region.or(region_fallback);
        Ok(options)
    }
}

/// Debug output that never shows the secret or the session token.
impl std::fmt::Debug for StorageOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let redact = |v: &Option<String>| v.as_ref().map(|_| "<redacted>");
        f.debug_struct("StorageOptions")
            .field("endpoint", &self.endpoint)
            .field("region", &self.region)
            .field("access_key_id", &self.access_key_id)
            .field("secret_access_key", &redact(&self.secret_access_key))
            .field("session_token", &redact(&self.session_token))
            .field("allow_http", &self.allow_http)
            .field("virtual_hosted_style", &self.virtual_hosted_style)
            .finish()
    }
}

fn parse_bool(name: &str, value: String) -> StorageResult<bool> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" | "1" | "yes" => Ok(true),
        "false" | "0" | "no" | "" => Ok(false),
        _ => Err(StorageError::InvalidOption {
            name: name.to_owned(),
            value,
            reason: "expected true or false".to_owned(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn env_map_reads_aws_names_and_prefers_the_specific_ones() {
        let vars = [
            ("AWS_ENDPOINT", "http://fallback:1"),
            ("AWS_ENDPOINT_URL", "http://minio:9000"),
            ("AWS_DEFAULT_REGION", "eu-west-1"),
            ("AWS_ACCESS_KEY_ID", "id"),
            ("AWS_SECRET_ACCESS_KEY", "hunter2"),
            ("AWS_ALLOW_HTTP", "true"),
            ("HOME", "/root"),
        ];
        let o = StorageOptions::from_env_map(vars).expect("valid options");
        assert_eq!(o.endpoint.as_deref(), Some("http://minio:9000"));
        assert_eq!(o.region.as_deref(), Some("eu-west-1"));
        assert_eq!(o.access_key_id.as_deref(), Some("id"));
        assert!(o.allow_http);
        assert!(!o.virtual_hosted_style);
        assert!(!format!("{o:?}").contains("hunter2"));
        assert!(StorageOptions::from_env_map([("AWS_ALLOW_HTTP", "maybe")]).is_err());
    }
}
