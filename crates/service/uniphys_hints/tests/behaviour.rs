//! The same behaviour cases against Redis (when `UNIPHYS_TEST_REDIS_URL` is set) and against
//! the in-process backend. Each Redis case uses its own key prefix.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use uniphys_hints::{Hints, HintsOptions, Progress, RateDecision, RateLimit, Wake};

/// A fresh pair of handles sharing one store: two connections for Redis, two clones for local.
type Pair = (Hints, Hints);

fn unique_prefix(case: &str) -> String {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or_default();
    format!(
        "uniphys_test:{case}:{}:{nanos}:{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    )
}

fn options() -> HintsOptions {
    HintsOptions {
        resubscribe_after: Duration::from_millis(100),
        progress_ttl: Duration::from_secs(3600),
        ..HintsOptions::default()
    }
}

/// Two Redis handles on the same prefix, or `None` (and a printed line) when no server is set.
fn redis_pair(case: &str) -> Option<Pair> {
    let Ok(url) = std::env::var("UNIPHYS_TEST_REDIS_URL") else {
        println!("skipped: UNIPHYS_TEST_REDIS_URL is not set ({case} on redis)");
        return None;
    };
    let prefix = unique_prefix(case);
    let a = Hints::redis_with_options(&url, &prefix, options()).expect("valid url");
    let b = Hints::redis_with_options(&url, &prefix, options()).expect("valid url");
    Some((a, b))
}

fn local_pair() -> Pair {
    let hints = Hints::local_with_options(options());
    (hints.clone(), hints)
}

/// Waits until the doorbell listens (Redis subscribes in the background).
async fn until_subscribed(is_subscribed: impl Fn() -> bool) {
    for _ in 0..200 {
        if is_subscribed() {
            return;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!("doorbell did not subscribe within 2 s");
}

/// Generates `#[tokio::test] fn {case}_redis` and `{case}_local` from `async fn case(Pair)`.
macro_rules! both_backends {
    ($($case:ident),* $(,)?) => {
        mod redis_backend {
            $(
                #[tokio::test]
                async fn $case() {
                    if let Some(pair) = super::redis_pair(stringify!($case)) {
                        let cleanup = pair.0.clone();
                        super::$case(pair).await;
                        cleanup.clear().await.expect("clear test keys");
                    }
                }
            )*
        }
        mod local_backend {
            $(
                #[tokio::test]
                async fn $case() {
                    super::$case(super::local_pair()).await;
                }
            )*
        }
    };
}

both_backends!(
    ring_wakes_its_stage_only,
    rings_coalesce_while_busy,
    rate_limit_is_shared_and_exact,
    rate_limit_rejects_impossible_requests,
    slots_respect_capacity_across_handles,
    expired_holder_frees_its_slot,
    progress_roundtrip_with_ttl,
    events_reach_subscribers_of_their_channel,
    losing_all_state_mid_use_breaks_nothing,
    ping_answers,
);

async fn ring_wakes_its_stage_only((a, b): Pair) {
    let mut ground = b.doorbell(&["ground".to_owned()]);
    let mut verify = b.doorbell(&["verify".to_owned(), "export".to_owned()]);
    until_subscribed(|| ground.is_subscribed() && verify.is_subscribed()).await;

    a.ring("ground").await.expect("ring");
    assert_eq!(ground.wait(Duration::from_secs(5)).await, Wake::Rung);
    assert_eq!(verify.wait(Duration::from_millis(200)).await, Wake::Timeout);

    a.ring("export").await.expect("ring");
    assert_eq!(verify.wait(Duration::from_secs(5)).await, Wake::Rung);
    assert_eq!(ground.wait(Duration::from_millis(200)).await, Wake::Timeout);
}

async fn rings_coalesce_while_busy((a, b): Pair) {
    let mut doorbell = b.doorbell(&["ground".to_owned()]);
    until_subscribed(|| doorbell.is_subscribed()).await;
    for _ in 0..5 {
        a.ring("ground").await.expect("ring");
    }
    // Rung once for the five rings made while nobody waited, then quiet.
    assert_eq!(doorbell.wait(Duration::from_secs(5)).await, Wake::Rung);
    // Let any ring still in flight arrive, then it must have been coalesced.
    tokio::time::sleep(Duration::from_millis(100)).await;
    let second = doorbell.wait(Duration::from_millis(10)).await;
    let third = doorbell.wait(Duration::from_millis(200)).await;
    assert!(
        second == Wake::Timeout || third == Wake::Timeout,
        "five rings woke the doorbell three times"
    );
    assert_eq!(
        doorbell.wait(Duration::from_millis(200)).await,
        Wake::Timeout
    );
}

async fn rate_limit_is_shared_and_exact((a, b): Pair) {
    // 5 a minute: one token back every 12 s, far longer than this test.
    let limit = RateLimit::new("lvlm", 5);
    let mut allowed = 0;
    for i in 0..5 {
        let hints = if i % 2 == 0 { &a } else { &b };
        if hints.try_acquire(&limit, 1).await.expect("try_acquire") == RateDecision::Allowed {
            allowed += 1;
        }
    }
    assert_eq!(allowed, 5);
    for hints in [&a, &b] {
        match hints.try_acquire(&limit, 1).await.expect("try_acquire") {
            RateDecision::RetryAfter(wait) => {
                assert!(wait > Duration::ZERO);
                assert!(wait <= Duration::from_secs(12), "wait {wait:?}");
            }
            RateDecision::Allowed => panic!("a sixth request got through a limit of 5"),
        }
    }
    // Another name is another bucket.
    let other = RateLimit::new("other", 1);
    assert_eq!(
        a.try_acquire(&other, 1).await.expect("try_acquire"),
        RateDecision::Allowed
    );
}

async fn rate_limit_rejects_impossible_requests((a, _b): Pair) {
    let limit = RateLimit::new("small", 2);
    let err = a.try_acquire(&limit, 3).await.expect_err("3 of 2");
    assert!(!err.is_unavailable());
    assert!(a.try_acquire(&RateLimit::new("zero", 0), 1).await.is_err());
}

async fn slots_respect_capacity_across_handles((a, b): Pair) {
    let ttl = Duration::from_secs(30);
    assert!(a.acquire_slot("gpu", 2, "w1", ttl).await.expect("acquire"));
    assert!(b.acquire_slot("gpu", 2, "w2", ttl).await.expect("acquire"));
    assert!(!a.acquire_slot("gpu", 2, "w3", ttl).await.expect("acquire"));
    assert!(!b.acquire_slot("gpu", 2, "w3", ttl).await.expect("acquire"));
    // Re-acquiring or renewing a held slot succeeds and does not take a second one.
    assert!(a.acquire_slot("gpu", 2, "w1", ttl).await.expect("acquire"));
    assert!(b.renew_slot("gpu", 2, "w2", ttl).await.expect("renew"));
    // Releasing frees a slot for the next holder, on the other handle.
    assert!(a.release_slot("gpu", "w1").await.expect("release"));
    assert!(!a.release_slot("gpu", "w1").await.expect("release twice"));
    assert!(b.acquire_slot("gpu", 2, "w3", ttl).await.expect("acquire"));
    assert!(!a.acquire_slot("gpu", 2, "w1", ttl).await.expect("acquire"));
    // Another pool is separate.
    assert!(a.acquire_slot("cpu", 1, "w1", ttl).await.expect("acquire"));
}

async fn expired_holder_frees_its_slot((a, b): Pair) {
    let short = Duration::from_millis(150);
    assert!(
        a.acquire_slot("gpu", 1, "crashed", short)
            .await
            .expect("acquire")
    );
    assert!(
        !b.acquire_slot("gpu", 1, "next", Duration::from_secs(30))
            .await
            .expect("acquire")
    );
    tokio::time::sleep(Duration::from_millis(400)).await;
    assert!(
        b.acquire_slot("gpu", 1, "next", Duration::from_secs(30))
            .await
            .expect("acquire")
    );
    // The crashed holder's renewal finds the pool full without it.
    assert!(
        !a.renew_slot("gpu", 1, "crashed", short)
            .await
            .expect("renew")
    );
}

async fn progress_roundtrip_with_ttl((a, b): Pair) {
    assert!(a.progress(42).await.expect("progress").is_empty());
    assert_eq!(a.progress_ttl(42).await.expect("ttl"), None);
    let ground = Progress::new(0.25, "grounding part 1 of 4");
    a.set_progress(42, "ground", &ground).await.expect("set");
    a.set_progress(42, "verify", &Progress::new(0.0, "queued"))
        .await
        .expect("set");
    a.set_progress(42, "verify", &Progress::new(1.0, "done"))
        .await
        .expect("set");
    let read = b.progress(42).await.expect("progress");
    assert_eq!(read.len(), 2);
    assert_eq!(read["ground"], ground);
    assert_eq!(read["verify"], Progress::new(1.0, "done"));
    assert!(b.progress(43).await.expect("progress").is_empty());
    let ttl = b
        .progress_ttl(42)
        .await
        .expect("ttl")
        .expect("a ttl is set");
    assert!(
        ttl > Duration::from_secs(3500) && ttl <= Duration::from_secs(3600),
        "{ttl:?}"
    );
    let err = a
        .set_progress(42, "ground", &Progress::new(1.5, "too far"))
        .await
        .expect_err("fraction > 1");
    assert!(!err.is_unavailable());
}

async fn events_reach_subscribers_of_their_channel((a, b): Pair) {
    let mut job_events = b.subscribe_events("job:7");
    let mut other = b.subscribe_events("job:8");
    until_subscribed(|| job_events.is_subscribed() && other.is_subscribed()).await;
    a.publish_event("job:7", r#"{"stage":"ground","state":"done"}"#)
        .await
        .expect("publish");
    a.publish_event("job:7", r#"{"stage":"verify","state":"running"}"#)
        .await
        .expect("publish");
    assert_eq!(
        job_events.next(Duration::from_secs(5)).await.as_deref(),
        Some(r#"{"stage":"ground","state":"done"}"#)
    );
    assert_eq!(
        job_events.next(Duration::from_secs(5)).await.as_deref(),
        Some(r#"{"stage":"verify","state":"running"}"#)
    );
    assert_eq!(other.next(Duration::from_millis(200)).await, None);
}

async fn losing_all_state_mid_use_breaks_nothing((a, b): Pair) {
    let limit = RateLimit::new("lvlm", 2);
    let ttl = Duration::from_secs(30);
    let mut doorbell = b.doorbell(&["ground".to_owned()]);
    until_subscribed(|| doorbell.is_subscribed()).await;
    assert_eq!(
        a.try_acquire(&limit, 2).await.expect("acquire"),
        RateDecision::Allowed
    );
    assert!(a.acquire_slot("gpu", 1, "w1", ttl).await.expect("acquire"));
    a.set_progress(1, "ground", &Progress::new(0.5, "half"))
        .await
        .expect("set");

    assert!(a.clear().await.expect("clear") >= 3);

    // Everything starts afresh: a full bucket, a free pool, no progress.
    assert_eq!(
        b.try_acquire(&limit, 2).await.expect("acquire"),
        RateDecision::Allowed
    );
    assert!(b.progress(1).await.expect("progress").is_empty());
    // The old holder re-takes its slot on renewal (there is room), so the pool stays bounded.
    assert!(a.renew_slot("gpu", 1, "w1", ttl).await.expect("renew"));
    assert!(!b.acquire_slot("gpu", 1, "w2", ttl).await.expect("acquire"));
    a.set_progress(1, "ground", &Progress::new(0.75, "three quarters"))
        .await
        .expect("set");
    assert_eq!(b.progress(1).await.expect("progress").len(), 1);
    // The doorbell still rings.
    a.ring("ground").await.expect("ring");
    assert_eq!(doorbell.wait(Duration::from_secs(5)).await, Wake::Rung);
}

async fn ping_answers((a, _b): Pair) {
    a.ping().await.expect("ping");
    assert!(a.is_healthy());
}
