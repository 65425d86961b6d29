//! Keyset pages of the listing routes: the `limit` a request may ask for, and the `next` cursor
//! of a page (the last key of a full page; none after the last page).

use crate::error::{ApiError, ApiResult};

/// `limit`, or `default` when absent; 400 unless it is within `1..=max`.
pub(crate) fn page_limit(limit: Option<u32>, default: u32, max: u32) -> ApiResult<u32> {
    let limit = limit.unwrap_or(default);
    if (1..=max).contains(&limit) {
        Ok(limit)
    } else {
        Err(ApiError::bad_request(
            "invalid_query",
            format!("limit must be between 1 and {max}, got {limit}"),
        ))
    }
}

/// The cursor after `keys` (the page's keys in order): the last one when the page is full.
pub(crate) fn next_cursor<K: ToString>(keys: &[K], limit: u32) -> Option<String> {
    (keys.len() == limit as usize)
        .then(|| keys.last().map(ToString::to_string))
        .flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_checked_and_only_a_full_page_has_a_next() {
        assert_eq!(page_limit(None, 50, 200).ok(), Some(50));
        assert_eq!(page_limit(Some(200), 50, 200).ok(), Some(200));
        assert!(page_limit(Some(0), 50, 200).is_err());
        assert!(page_limit(Some(201), 50, 200).is_err());
        assert_eq!(next_cursor(&["b", "a"], 2), Some("a".to_owned()));
        assert_eq!(next_cursor(&["b"], 2), None);
        assert_eq!(next_cursor::<&str>(&[], 2), None);
    }
}
