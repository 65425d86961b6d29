//! Ids in paths and query strings: `asset_12` or `12`; anything else answers 400.

use uniphys_queue::{AssetId, JobId};

use crate::error::{ApiError, ApiResult};

/// Parses an asset id given as `asset_12` or `12`; `field` names it in the error.
pub(crate) fn asset_id(field: &str, raw: &str) -> ApiResult<AssetId> {
    positive(field, AssetId::PREFIX, raw).map(AssetId)
}

/// Parses a job id given as `job_12` or `12`; `field` names it in the error.
pub(crate) fn job_id(field: &str, raw: &str) -> ApiResult<JobId> {
    positive(field, JobId::PREFIX, raw).map(JobId)
}

fn positive(field: &str, prefix: &str, raw: &str) -> ApiResult<i64> {
    let digits = raw.strip_prefix(prefix).unwrap_or(raw);
    digits
        .bytes()
        .all(|b| b.is_ascii_digit())
        .then(|| digits.parse::<i64>().ok())
        .flatten()
        .filter(|n| *n > 0)
        .ok_or_else(|| {
            ApiError::bad_request(
                "invalid_id",
                format!("{field} must be a positive integer (or {prefix}<n>), got {raw:?}"),
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_read_with_or_without_their_prefix() {
        assert_eq!(asset_id("asset_id", "asset_12").ok(), Some(AssetId(12)));
        assert_eq!(asset_id("asset_id", "12").ok(), Some(AssetId(12)));
        assert_eq!(job_id("job_id", "job_7").ok(), Some(JobId(7)));
    }

    #[test]
    fn bad_ids_name_the_field() {
        for raw in [
            "0",
            "-3",
            "+3",
            "job_3",
            "abc",
            "",
            "asset_",
            "99999999999999999999",
        ] {
            let err = asset_id("asset_id", raw).expect_err(raw);
            assert!(
                err.to_string()
                    .starts_with("asset_id must be a positive integer"),
                "{err}"
            );
        }
    }
}
