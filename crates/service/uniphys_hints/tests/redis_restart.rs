//! A Redis that goes away and comes back: calls fail fast while it is down, and the handle and
//! its doorbell recover on their own afterwards. Runs a private `redis-server` on a free
//! loopback port (skipped when the binary is not installed).

use std::net::TcpListener;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use uniphys_hints::{Hints, HintsOptions, Progress, Wake};

const HANG_GUARD: Duration = Duration::from_secs(2);

/// A `redis-server` child process, killed on drop.
struct Server {
    child: Child,
}

impl Server {
    fn start(port: u16) -> Option<Self> {
        let child = Command::new("redis-server")
            .args(["--port", &port.to_string(), "--bind", "127.0.0.1"])
            .args(["--save", "", "--appendonly", "no"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .ok()?;
        Some(Self { child })
    }

    fn stop(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn free_port() -> u16 {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind an ephemeral port");
    listener.local_addr().expect("local addr").port()
}

/// Retries `ping` until it answers, for at most `limit`.
async fn until_up(hints: &Hints, limit: Duration) {
    let started = Instant::now();
    while hints.ping().await.is_err() {
        assert!(
            started.elapsed() < limit,
            "redis not reachable after {limit:?}"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

async fn until(what: &str, limit: Duration, check: impl Fn() -> bool) {
    let started = Instant::now();
    while !check() {
        assert!(started.elapsed() < limit, "{what} not within {limit:?}");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

#[tokio::test]
async fn recovers_after_redis_restart() {
    let port = free_port();
    let Some(server) = Server::start(port) else {
        println!("skipped: redis-server is not installed");
        return;
    };
    let url = format!("redis://127.0.0.1:{port}/");
    let options = HintsOptions {
        resubscribe_after: Duration::from_millis(100),
        ..HintsOptions::default()
    };
    let hints = Hints::redis_with_options(&url, "restart", options).expect("valid url");
    until_up(&hints, Duration::from_secs(10)).await;
    let mut doorbell = hints.doorbell(&["ground".to_owned()]);
    until("first subscription", Duration::from_secs(5), || {
        doorbell.is_subscribed()
    })
    .await;
    hints.ring("ground").await.expect("ring while up");
    assert_eq!(doorbell.wait(Duration::from_secs(5)).await, Wake::Rung);

    server.stop();

    until("doorbell noticing the loss", Duration::from_secs(5), || {
        !doorbell.is_subscribed()
    })
    .await;
    for _ in 0..3 {
        let started = Instant::now();
        assert!(hints.ring("ground").await.is_err());
        assert!(
            hints
                .set_progress(1, "ground", &Progress::new(0.5, "half"))
                .await
                .is_err()
        );
        assert!(started.elapsed() < HANG_GUARD);
        assert_eq!(
            doorbell.wait(Duration::from_millis(100)).await,
            Wake::Timeout
        );
    }
    assert!(!hints.is_healthy());

    let _server = Server::start(port).expect("restart redis-server");
    until_up(&hints, Duration::from_secs(10)).await;
    assert!(hints.is_healthy());
    hints
        .set_progress(1, "ground", &Progress::new(0.5, "half"))
        .await
        .expect("set_progress after restart");
    until("resubscription", Duration::from_secs(5), || {
        doorbell.is_subscribed()
    })
    .await;
    hints.ring("ground").await.expect("ring after restart");
    assert_eq!(doorbell.wait(Duration::from_secs(5)).await, Wake::Rung);
}
