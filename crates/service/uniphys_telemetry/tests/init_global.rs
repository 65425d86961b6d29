//! `init` installs the process-wide subscriber once (its own test binary: it sets globals).

use uniphys_telemetry::{LogFormat, TelemetryConfig, TelemetryError, init};

#[test]
fn init_installs_once_and_rejects_a_bad_filter() {
    let bad = TelemetryConfig::new("t").with_log_filter("info,=[");
    assert!(
        matches!(init(&bad), Err(TelemetryError::LogFilter { .. })),
        "bad filter accepted"
    );
    let config = TelemetryConfig::new("t")
        .with_log_format(LogFormat::Json)
        .with_log_filter("debug");
    let guard = init(&config).expect("first init");
    tracing::info!(answer = 42, "json line");
    assert!(tracing::enabled!(tracing::Level::DEBUG), "filter applied");
    assert!(!tracing::enabled!(tracing::Level::TRACE), "filter applied");
    assert!(
        matches!(init(&config), Err(TelemetryError::SubscriberAlreadySet)),
        "second init accepted"
    );
    guard.shutdown().expect("nothing to flush");
}
