use std::time::{Duration, SystemTime};

/// Longest `Retry-After` read from a header (one day); the policy's `max_delay` caps it further.
pub const MAX_RETRY_AFTER: Duration = Duration::from_secs(86_400);

/// A `Retry-After` value as a wait from `now`: delay seconds (`"2"`, also `"0.5"`) or an HTTP
/// date (`"Wed, 21 Oct 2015 07:28:00 GMT"`; a date in the past is no wait), at most
/// [`MAX_RETRY_AFTER`]. `None` for anything else (negative, not a number or a date).
#[must_use]
pub fn parse_retry_after(value: &str, now: SystemTime) -> Option<Duration> {
    let value = value.trim();
    if let Ok(seconds) = value.parse::<f64>() {
        return (seconds.is_finite() && seconds >= 0.0)
            .then(|| Duration::from_secs_f64(seconds.min(MAX_RETRY_AFTER.as_secs_f64())));
    }
    let date = httpdate::parse_http_date(value).ok()?;
    Some(
        date.duration_since(now)
            .unwrap_or(Duration::ZERO)
            .min(MAX_RETRY_AFTER),
    )
}

/// The wait a response asks for: `retry-after-ms` (milliseconds, as OpenAI-compatible servers
/// send) before `retry-after`.
pub(crate) fn from_headers(headers: &reqwest::header::HeaderMap) -> Option<Duration> {
    let text = |name: &str| headers.get(name).and_then(|v| v.to_str().ok());
    let millis = text("retry-after-ms")
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|ms| ms.is_finite() && *ms >= 0.0)
        .map(|ms| Duration::from_secs_f64((ms / 1000.0).min(MAX_RETRY_AFTER.as_secs_f64())));
    millis.or_else(|| text("retry-after").and_then(|v| parse_retry_after(v, SystemTime::now())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(secs: u64) -> SystemTime {
        SystemTime::UNIX_EPOCH + Duration::from_secs(secs)
    }

    #[test]
    fn seconds_are_read_and_capped() {
        let now = SystemTime::now();
        assert_eq!(parse_retry_after(" 2 ", now), Some(Duration::from_secs(2)));
        assert_eq!(parse_retry_after("0", now), Some(Duration::ZERO));
        assert_eq!(
            parse_retry_after("0.5", now),
            Some(Duration::from_millis(500))
        );
        assert_eq!(parse_retry_after("9999999", now), Some(MAX_RETRY_AFTER));
        assert_eq!(parse_retry_after("-1", now), None);
        assert_eq!(parse_retry_after("soon", now), None);
        assert_eq!(parse_retry_after("", now), None);
    }

    #[test]
    fn http_dates_are_read_relative_to_now() {
        // 1445412480 is Wed, 21 Oct 2015 07:28:00 GMT.
        let date = "Wed, 21 Oct 2015 07:28:00 GMT";
        assert_eq!(
            parse_retry_after(date, at(1_445_412_480 - 30)),
            Some(Duration::from_secs(30))
        );
        assert_eq!(
            parse_retry_after(date, at(1_445_412_480 + 5)),
            Some(Duration::ZERO)
        );
        assert_eq!(
            parse_retry_after(date, at(1_445_412_480 - 10 * 86_400)),
            Some(MAX_RETRY_AFTER)
        );
        assert_eq!(
            parse_retry_after("Wed, 32 Oct 2015 07:28:00 GMT", at(0)),
            None
        );
    }

    #[test]
    fn milliseconds_come_before_seconds() {
        let mut headers = reqwest::header::HeaderMap::new();
        assert_eq!(from_headers(&headers), None);
        headers.insert("retry-after", "2".parse().unwrap());
        assert_eq!(from_headers(&headers), Some(Duration::from_secs(2)));
        headers.insert("retry-after-ms", "250".parse().unwrap());
        assert_eq!(from_headers(&headers), Some(Duration::from_millis(250)));
    }
}
