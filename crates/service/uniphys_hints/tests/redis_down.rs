//! With nothing listening at the Redis address, every call fails fast and doorbells fall back
//! to their poll interval. The elapsed-time bounds are hang guards, not performance targets.

use std::time::{Duration, Instant};

use uniphys_hints::{Hints, Progress, RateLimit, Wake};

/// Port 1 on loopback: nothing listens there, so connections are refused at once.
const DEAD_URL: &str = "redis://127.0.0.1:1/";
const HANG_GUARD: Duration = Duration::from_secs(2);

fn dead() -> Hints {
    Hints::redis(DEAD_URL, "uniphys_test:dead").expect("a down server is not an error at start")
}

#[tokio::test]
async fn commands_fail_fast() {
    let hints = dead();
    for round in 0..3 {
        let started = Instant::now();
        let err = hints
            .ring("ground")
            .await
            .expect_err("ring with redis down");
        assert!(err.is_unavailable(), "{err}");
        assert!(started.elapsed() < HANG_GUARD, "ring round {round}");

        let started = Instant::now();
        let err = hints
            .try_acquire(&RateLimit::new("lvlm", 10), 1)
            .await
            .expect_err("try_acquire with redis down");
        assert!(err.is_unavailable(), "{err}");
        assert!(started.elapsed() < HANG_GUARD, "try_acquire round {round}");

        let started = Instant::now();
        let err = hints
            .set_progress(1, "ground", &Progress::new(0.5, "half"))
            .await
            .expect_err("set_progress with redis down");
        assert!(err.is_unavailable(), "{err}");
        assert!(started.elapsed() < HANG_GUARD, "set_progress round {round}");

        let started = Instant::now();
        assert!(
            hints
                .acquire_slot("gpu", 1, "w1", Duration::from_secs(10))
                .await
                .is_err()
        );
        assert!(hints.progress(1).await.is_err());
        assert!(hints.ping().await.is_err());
        assert!(
            started.elapsed() < HANG_GUARD * 3,
            "other calls round {round}"
        );
    }
    assert!(!hints.is_healthy());
}

#[tokio::test]
async fn doorbell_wait_falls_back_to_polling() {
    let hints = dead();
    let mut doorbell = hints.doorbell(&["ground".to_owned()]);
    for _ in 0..3 {
        let started = Instant::now();
        assert_eq!(
            doorbell.wait(Duration::from_millis(200)).await,
            Wake::Timeout
        );
        let elapsed = started.elapsed();
        assert!(elapsed >= Duration::from_millis(190), "{elapsed:?}");
        assert!(elapsed < HANG_GUARD, "{elapsed:?}");
    }
    assert!(!doorbell.is_subscribed());
}

#[tokio::test]
async fn invalid_url_is_an_error() {
    let err = Hints::redis("not a url", "p").expect_err("invalid url");
    assert!(!err.is_unavailable());
}
