use std::path::Path;
use std::sync::Arc;

use object_store::ObjectStore;
use object_store::aws::{AmazonS3Builder, S3ConditionalPut, S3CopyIfNotExists};
use object_store::prefix::PrefixStore;

use crate::key::validate_key;
use crate::{ArtifactStore, StorageError, StorageOptions, StorageResult};

impl ArtifactStore {
    /// Opens the store named by `url`:
    /// - `file:///abs/dir` or a plain path: a local directory, created if missing;
    /// - `memory://`: an in-memory store (tests, dry runs);
    /// - `s3://bucket` or `s3://bucket/prefix`: an S3-compatible bucket configured by `options`
    ///   (endpoint, region, keys, `allow_http`, path or virtual-hosted style). The bucket must exist.
    ///
    /// S3 stores are built with `If-None-Match: *` conditional puts (what [`ArtifactStore::put_once`]
    /// relies on) and with multipart-copy create-only copies (what [`ArtifactStore::put_file`]
    /// relies on); both are answered by AWS S3 since 2024 and by MinIO.
    pub fn from_url(url: &str, options: &StorageOptions) -> StorageResult<Self> {
        let invalid = |reason: &str| StorageError::InvalidUrl {
            url: url.to_owned(),
            reason: reason.to_owned(),
        };
        if let Some(rest) = url.strip_prefix("memory://") {
            if !rest.is_empty() {
                return Err(invalid("memory:// takes no path"));
            }
            return Ok(Self::in_memory());
        }
        if let Some(rest) = url.strip_prefix("file://") {
            // `file:///abs` and `file://localhost/abs`; anything else names another host.
            let path = rest.strip_prefix("localhost").unwrap_or(rest);
            if !path.starts_with('/') {
                return Err(invalid(
                    "file:// URLs need an absolute path (file:///abs/dir)",
                ));
            }
            return Self::local(Path::new(path));
        }
        if let Some(rest) = url.strip_prefix("s3://") {
            let (bucket, prefix) = rest.split_once('/').unwrap_or((rest, ""));
            if bucket.is_empty() {
                return Err(invalid("s3:// URLs need a bucket (s3://bucket/prefix)"));
            }
            let prefix = prefix.trim_end_matches('/');
            if !prefix.is_empty() {
                validate_key(prefix).map_err(|_| invalid("the prefix is not a valid key"))?;
            }
            return Ok(Self::from_object_store(s3_store(bucket, prefix, options)?));
        }
        if url.contains("://") {
            return Err(invalid(
                "supported schemes are file://, memory:// and s3://",
            ));
        }
        if url.is_empty() {
            return Err(invalid("empty"));
        }
        Self::local(Path::new(url))
    }
}

fn s3_store(
    bucket: &str,
    prefix: &str,
    options: &StorageOptions,
) -> StorageResult<Arc<dyn ObjectStore>> {
    let mut builder = AmazonS3Builder::new()
        .with_bucket_name(bucket)
        .with_region(options.region.as_deref().unwrap_or("us-east-1"))
        .with_allow_http(options.allow_http)
        .with_virtual_hosted_style_request(options.virtual_hosted_style)
        .with_conditional_put(S3ConditionalPut::ETagMatch)
        .with_copy_if_not_exists(S3CopyIfNotExists::Multipart);
    if let Some(endpoint) = &options.endpoint {
        builder = builder.with_endpoint(endpoint);
    }
    if let Some(id) = &options.access_key_id {
        builder = builder.with_access_key_id(id);
    }
    if let Some(secret) = &options.secret_access_key {
        builder = builder.with_secret_access_key(secret);
    }
    if let Some(token) = &options.session_token {
        builder = builder.with_token(token);
    }
    let s3 = builder.build().map_err(|source| StorageError::Store {
        key: format!("s3://{bucket}"),
        source,
    })?;
    Ok(if prefix.is_empty() {
        Arc::new(s3)
    } else {
        Arc::new(PrefixStore::new(s3, prefix))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urls_pick_the_store_and_bad_ones_are_rejected() {
        let dir = tempfile::tempdir().expect("temp dir");
        let plain = dir.path().join("plain");
        let plain_str = plain.to_str().expect("utf-8 temp path");
        let opts = StorageOptions::default();
        ArtifactStore::from_url(plain_str, &opts).expect("plain path");
        assert!(plain.is_dir());
        let url = format!("file://{}", dir.path().join("viaurl").display());
        ArtifactStore::from_url(&url, &opts).expect("file url");
        assert!(dir.path().join("viaurl").is_dir());
        ArtifactStore::from_url("memory://", &opts).expect("memory");
        ArtifactStore::from_url("s3://bucket/some/prefix", &opts).expect("s3 url builds");
        for bad in [
            "",
            "file://relative/dir",
            "gs://bucket",
            "s3://",
            "s3:///x",
            "s3://b/../x",
            "memory://x",
        ] {
            assert!(
                ArtifactStore::from_url(bad, &opts).is_err(),
                "{bad:?} should be rejected"
            );
        }
    }
}
