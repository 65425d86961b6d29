//! The accept loop: HTTP/1 connections with a deadline for a request's headers and a cap on
//! the connections one client address holds open, so a slow or greedy client (slowloris: headers
//! sent a byte at a time, many idle sockets) cannot tie up the server.

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use axum::Router;
use hyper::server::conn::http1;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use tokio::net::TcpListener;
use tokio::sync::watch;
use tokio::task::JoinSet;

/// Limits on the connections of [`serve_with_limits`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConnectionLimits {
    /// A request's headers must arrive within this time of its first byte (and an idle
    /// keep-alive connection is closed after it). Default 10 s.
    pub header_read_timeout: Duration,
    /// Connections one client address may hold open at once; more are closed as soon as they
    /// are accepted. Default 64.
    pub max_connections_per_address: usize,
}

impl Default for ConnectionLimits {
    fn default() -> Self {
        Self {
            header_read_timeout: Duration::from_secs(10),
            max_connections_per_address: 64,
        }
    }
}

/// Open connections per client address.
#[derive(Clone, Default)]
struct OpenCounts(Arc<Mutex<HashMap<IpAddr, usize>>>);

impl OpenCounts {
    /// Counts a connection from `address` unless it already holds `cap`.
    fn try_open(&self, address: IpAddr, cap: usize) -> Option<OpenGuard> {
        let mut counts = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let open = counts.entry(address).or_insert(0);
        if *open >= cap {
            return None;
        }
        *open += 1;
        Some(OpenGuard {
            counts: self.clone(),
            address,
        })
    }
}

/// Uncounts its connection when dropped.
struct OpenGuard {
    counts: OpenCounts,
    address: IpAddr,
}

impl Drop for OpenGuard {
    fn drop(&mut self) {
        let mut counts = self.counts.0.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(open) = counts.get_mut(&self.address) {
            *open -= 1;
            if *open == 0 {
                counts.remove(&self.address);
            }
        }
    }
}

/// Serves `router` on `listener` within `limits` until `shutdown` completes; then stops
/// accepting, lets the requests in flight finish and returns.
///
/// Errors: none from connections (each is logged and closed); accept errors are logged and
/// retried after a short pause (a full file table must not stop the server).
pub async fn serve_with_limits(
    listener: TcpListener,
    router: Router,
    limits: ConnectionLimits,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    let counts = OpenCounts::default();
    let (stop_tx, stop_rx) = watch::channel(false);
    let mut connections = JoinSet::new();
    tokio::pin!(shutdown);
    loop {
        let (stream, peer) = tokio::select! {
            () = &mut shutdown => break,
            accepted = listener.accept() => match accepted {
                Ok(accepted) => accepted,
                Err(e) => {
                    tracing::warn!(error = %e, "accepting a connection failed");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
            Some(_) = connections.join_next(), if !connections.is_empty() => continue,
        };
        let Some(guard) = counts.try_open(peer.ip(), limits.max_connections_per_address) else {
            tracing::warn!(
                client = %peer.ip(),
                cap = limits.max_connections_per_address,
                "connection refused: the address holds its cap of open connections"
            );
            drop(stream);
            continue;
        };
        connections.spawn(serve_connection(
            stream,
            peer,
            router.clone(),
            limits,
            stop_rx.clone(),
            guard,
        ));
    }
    // Dropping the listener refuses new connections; open ones finish their requests.
    drop(listener);
    let _ = stop_tx.send(true);
    while connections.join_next().await.is_some() {}
    Ok(())
}

/// One connection until it closes, or until `stop` turns true and its request in flight ends.
async fn serve_connection(
    stream: tokio::net::TcpStream,
    peer: SocketAddr,
    router: Router,
    limits: ConnectionLimits,
    mut stop: watch::Receiver<bool>,
    _guard: OpenGuard,
) {
    // Answers go out as written: with Nagle's algorithm a keep-alive client's next request
    // waits for the delayed ACK of a response's last small packet (40 ms per request here).
    if let Err(e) = stream.set_nodelay(true) {
        tracing::debug!(client = %peer, error = %e, "TCP_NODELAY not set");
    }
    let mut builder = http1::Builder::new();
    builder
        .timer(TokioTimer::new())
        .header_read_timeout(limits.header_read_timeout);
    let connection =
        builder.serve_connection(TokioIo::new(stream), TowerToHyperService::new(router));
    tokio::pin!(connection);
    loop {
        tokio::select! {
            served = connection.as_mut() => {
                if let Err(e) = served {
                    tracing::debug!(client = %peer, error = %e, "connection closed with an error");
                }
                return;
            }
            changed = stop.changed() => {
                if changed.is_err() || *stop.borrow() {
                    connection.as_mut().graceful_shutdown();
                    // The connection future finishes once its request in flight is answered.
                    let _ = connection.as_mut().await;
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_address_holds_at_most_its_cap_and_a_closed_connection_frees_a_place() {
        let counts = OpenCounts::default();
        let a: IpAddr = [127, 0, 0, 1].into();
        let b: IpAddr = [127, 0, 0, 2].into();
        let first = counts.try_open(a, 2).expect("first");
        let _second = counts.try_open(a, 2).expect("second");
        assert!(
            counts.try_open(a, 2).is_none(),
            "a third from the same address"
        );
        assert!(
            counts.try_open(b, 2).is_some(),
            "another address has its own cap"
        );
        drop(first);
        assert!(counts.try_open(a, 2).is_some(), "a place freed");
    }
}
