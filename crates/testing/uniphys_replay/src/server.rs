//! The server: an acceptor thread and one thread per connection.

use std::collections::BTreeMap;
use std::io::{BufReader, ErrorKind, Read, Write};
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, Shutdown, SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::Duration;

use crate::http::{read_request, response_head};
use crate::{Fault, Recording, ReplayError, ReplayResult, Reply};

/// Decides the reply to each request (a [`Recording`] or a closure of a test).
pub type Responder = Arc<dyn Fn(&RecordedRequest) -> Reply + Send + Sync>;

/// A request as the server received it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecordedRequest {
    /// HTTP method as sent (`"POST"`).
    pub method: String,
    /// Request target as sent, query included (`"/v1/masks"`).
    pub path: String,
    /// Headers with lower-case names; repeated headers joined with `", "`.
    pub headers: BTreeMap<String, String>,
    /// The body (chunked bodies joined).
    pub body: Vec<u8>,
}

impl RecordedRequest {
    /// The body as text (invalid UTF-8 replaced).
    #[must_use]
    pub fn body_text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }
}

/// How often a hung answer checks whether the client left or the server stopped.
const HANG_POLL: Duration = Duration::from_millis(50);

struct Shared {
    responder: Responder,
    stopped: Mutex<bool>,
    stop_signal: Condvar,
    requests: Mutex<Vec<RecordedRequest>>,
    in_flight: AtomicUsize,
    max_in_flight: AtomicUsize,
    connections: AtomicUsize,
    open: Mutex<BTreeMap<usize, TcpStream>>,
    workers: Mutex<Vec<JoinHandle<()>>>,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

impl Shared {
    fn is_stopped(&self) -> bool {
        *lock(&self.stopped)
    }

    /// Waits `duration` or until the server stops; true if it stopped.
    fn wait(&self, duration: Duration) -> bool {
        let guard = lock(&self.stopped);
        let (guard, _) = self
            .stop_signal
            .wait_timeout_while(guard, duration, |stopped| !*stopped)
            .unwrap_or_else(PoisonError::into_inner);
        *guard
    }
}

/// Counts a request as being answered while alive.
struct InFlight<'a>(&'a Shared);

impl<'a> InFlight<'a> {
    fn enter(shared: &'a Shared) -> Self {
        let now = shared.in_flight.fetch_add(1, Ordering::SeqCst) + 1;
        shared.max_in_flight.fetch_max(now, Ordering::SeqCst);
        Self(shared)
    }
}

impl Drop for InFlight<'_> {
    fn drop(&mut self) {
        self.0.in_flight.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A running replay server. Stops (releasing every connection, hung ones included) on
/// [`ReplayServer::stop`] or when dropped.
pub struct ReplayServer {
    address: SocketAddr,
    shared: Arc<Shared>,
    acceptor: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for ReplayServer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ReplayServer")
            .field("address", &self.address)
            .finish_non_exhaustive()
    }
}

impl ReplayServer {
    /// Plays `recording` on a free port of 127.0.0.1.
    ///
    /// # Errors
    /// [`ReplayError::Bind`] or [`ReplayError::Spawn`].
    pub fn start(recording: Recording) -> ReplayResult<Self> {
        Self::bind("127.0.0.1:0", recording.into_responder())
    }

    /// Answers every request with `responder` on a free port of 127.0.0.1.
    ///
    /// # Errors
    /// [`ReplayError::Bind`] or [`ReplayError::Spawn`].
    pub fn start_with(responder: Responder) -> ReplayResult<Self> {
        Self::bind("127.0.0.1:0", responder)
    }

    /// Answers every request with `responder` on `address` (`"127.0.0.1:0"` for a free port).
    ///
    /// # Errors
    /// [`ReplayError::Bind`] or [`ReplayError::Spawn`].
    pub fn bind(address: &str, responder: Responder) -> ReplayResult<Self> {
        let bind_error = |source| ReplayError::Bind {
            address: address.to_owned(),
            source,
        };
        let listener = TcpListener::bind(address).map_err(bind_error)?;
        let local = listener.local_addr().map_err(bind_error)?;
        let shared = Arc::new(Shared {
            responder,
            stopped: Mutex::new(false),
            stop_signal: Condvar::new(),
            requests: Mutex::new(Vec::new()),
            in_flight: AtomicUsize::new(0),
            max_in_flight: AtomicUsize::new(0),
            connections: AtomicUsize::new(0),
            open: Mutex::new(BTreeMap::new()),
            workers: Mutex::new(Vec::new()),
        });
        let acceptor_shared = Arc::clone(&shared);
        let acceptor = std::thread::Builder::new()
            .name("replay-accept".to_owned())
            .spawn(move || accept_loop(&listener, &acceptor_shared))
            .map_err(ReplayError::Spawn)?;
        Ok(Self {
            address: reachable(local),
            shared,
            acceptor: Some(acceptor),
        })
    }

    /// Base URL, e.g. `http://127.0.0.1:40123` (no trailing slash).
    #[must_use]
    pub fn url(&self) -> String {
        format!("http://{}", self.address)
    }

    /// The address the server listens on.
    #[must_use]
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// Every request received so far, in arrival order.
    #[must_use]
    pub fn requests(&self) -> Vec<RecordedRequest> {
        lock(&self.shared.requests).clone()
    }

    /// The largest number of requests that were being answered at the same time.
    #[must_use]
    pub fn max_in_flight(&self) -> usize {
        self.shared.max_in_flight.load(Ordering::SeqCst)
    }

    /// TCP connections accepted so far (keep-alive clients reuse one).
    #[must_use]
    pub fn connection_count(&self) -> usize {
        self.shared.connections.load(Ordering::SeqCst)
    }

    /// Stops accepting, closes every connection (hung answers included) and joins all threads.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        let Some(acceptor) = self.acceptor.take() else {
            return;
        };
        *lock(&self.shared.stopped) = true;
        self.shared.stop_signal.notify_all();
        // Wake the acceptor from `accept` with a connection of our own.
        let _ = TcpStream::connect_timeout(&self.address, Duration::from_secs(1));
        let _ = acceptor.join();
        for stream in lock(&self.shared.open).values() {
            let _ = stream.shutdown(Shutdown::Both);
        }
        let workers = std::mem::take(&mut *lock(&self.shared.workers));
        for worker in workers {
            let _ = worker.join();
        }
    }
}

impl Drop for ReplayServer {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// The address a client can connect to (loopback instead of an unspecified address).
fn reachable(local: SocketAddr) -> SocketAddr {
    match local.ip() {
        IpAddr::V4(ip) if ip.is_unspecified() => {
            SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), local.port())
        }
        IpAddr::V6(ip) if ip.is_unspecified() => {
            SocketAddr::new(IpAddr::V6(Ipv6Addr::LOCALHOST), local.port())
        }
        _ => local,
    }
}

fn accept_loop(listener: &TcpListener, shared: &Arc<Shared>) {
    for stream in listener.incoming() {
        if shared.is_stopped() {
            return;
        }
        let Ok(stream) = stream else {
            // Out of descriptors or a connection reset before accept: do not spin.
            std::thread::sleep(Duration::from_millis(10));
            continue;
        };
        let Ok(registered) = stream.try_clone() else {
            continue;
        };
        let _ = stream.set_nodelay(true);
        let id = shared.connections.fetch_add(1, Ordering::SeqCst);
        lock(&shared.open).insert(id, registered);
        let worker_shared = Arc::clone(shared);
        let spawned = std::thread::Builder::new()
            .name(format!("replay-conn-{id}"))
            .spawn(move || {
                serve_connection(&worker_shared, stream);
                lock(&worker_shared.open).remove(&id);
            });
        let mut workers = lock(&shared.workers);
        workers.retain(|worker| !worker.is_finished());
        match spawned {
            Ok(worker) => workers.push(worker),
            Err(_) => {
                lock(&shared.open).remove(&id);
            }
        }
    }
}

fn serve_connection(shared: &Shared, stream: TcpStream) {
    let Ok(read_half) = stream.try_clone() else {
        return;
    };
    let mut reader = BufReader::with_capacity(256 * 1024, read_half);
    let mut writer = stream;
    loop {
        if shared.is_stopped() {
            return;
        }
        let incoming = match read_request(&mut reader, &mut writer) {
            Ok(Some(incoming)) => incoming,
            Ok(None) => return,
            Err(error) => {
                if error.kind() == ErrorKind::InvalidData {
                    let reply = Reply::json(400, serde_json::json!({"error": error.to_string()}));
                    let _ = write_reply(&mut writer, &reply, false);
                }
                return;
            }
        };
        lock(&shared.requests).push(incoming.request.clone());
        let _in_flight = InFlight::enter(shared);
        let reply = (shared.responder)(&incoming.request);
        if reply.delay_ms > 0 && shared.wait(Duration::from_millis(reply.delay_ms)) {
            return;
        }
        match reply.fault {
            Some(Fault::Hang) => {
                hang(shared, &mut reader);
                return;
            }
            Some(Fault::CloseWithoutReply) => {
                let _ = writer.shutdown(Shutdown::Both);
                return;
            }
            Some(Fault::Truncate { keep_bytes }) => {
                let body = reply.body_bytes();
                let head = response_head(
                    reply.status,
                    &reply.headers,
                    reply.json.is_some() && !reply.has_content_type(),
                    body.len(),
                    false,
                );
                let kept = body.get(..keep_bytes.min(body.len())).unwrap_or_default();
                let _ = writer
                    .write_all(&head)
                    .and_then(|()| writer.write_all(kept))
                    .and_then(|()| writer.flush());
                let _ = writer.shutdown(Shutdown::Both);
                return;
            }
            None => {
                if write_reply(&mut writer, &reply, incoming.keep_alive).is_err()
                    || !incoming.keep_alive
                {
                    return;
                }
            }
        }
    }
}

fn write_reply(writer: &mut TcpStream, reply: &Reply, keep_alive: bool) -> std::io::Result<()> {
    let body = reply.body_bytes();
    let head = response_head(
        reply.status,
        &reply.headers,
        reply.json.is_some() && !reply.has_content_type(),
        body.len(),
        keep_alive,
    );
    writer.write_all(&head)?;
    writer.write_all(&body)?;
    writer.flush()
}

/// Holds the connection without answering until the client closes it or the server stops.
fn hang(shared: &Shared, reader: &mut BufReader<TcpStream>) {
    if reader.get_ref().set_read_timeout(Some(HANG_POLL)).is_err() {
        return;
    }
    let mut scratch = [0u8; 4096];
    while !shared.is_stopped() {
        match reader.read(&mut scratch) {
            Ok(0) => return,
            Ok(_) => {}
            Err(error) if matches!(error.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            Err(_) => return,
        }
    }
}
