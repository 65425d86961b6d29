//! A TEST model server: std-only HTTP/1.1 on a local port that answers `POST /v1/predict` from
//! fixed geometric rules, not from a model. For client tests and local wiring only.
//!
//! Rules, per part, from the part's feature rows in the model frame: extents sorted small to
//! large, `ratio = smallest / largest`; kinematics: `ratio < 0.2` → `"C"` (a thin panel: door,
//! lid) with range `[0, 0.25]` (a quarter turn), `ratio < 0.6` → `"B"` with range
//! `[0, largest / 2]`, else `null`; axis = the longest axis of the part's box as integer
//! `{theta, phi}` degrees; pivot = centroid of the part's points, 4 decimals. Physics: wood
//! (0.7 g/cm^3, 10 GPa, 4 HV, 0.3, 0.45), affordance 2, graspable if `ratio < 0.2`. Structure:
//! members = the part itself. Object level: `"object"`, `"Other/Unknown"`, dimensions = the
//! object's model-frame extents x 50 cm, 1 kg.
//!
//! Faults are injected by the sample id: after a `#`, comma-separated `<fault>x<n>` items apply
//! in turn to the first requests of that sample id (`s#429x2,500x1`: two 429s, one 500, then
//! answers). Faults: `429` (with `Retry-After: 0`), `500`, `malformed` (truncated JSON with
//! status 200), `slow<ms>` (waits before answering, e.g. `slow2000x1`).

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::Duration;

use crate::FeatureRow;
use crate::contract::{
    AxisAnswer, ObjectAnswer, PartAnswer, PhysicsAnswer, PredictRequest, PredictResponse, Task,
};

/// Largest request body the test server reads.
const MAX_BODY_BYTES: usize = 256 * 1024 * 1024;

#[derive(Debug, Default)]
struct State {
    stop: AtomicBool,
    predict_requests: AtomicUsize,
    attempts_by_sample: Mutex<HashMap<String, u32>>,
}

/// A running test server; stops when dropped.
#[derive(Debug)]
pub struct TestServer {
    addr: SocketAddr,
    state: Arc<State>,
    acceptor: Option<JoinHandle<()>>,
}

impl TestServer {
    /// Starts on a free loopback port.
    ///
    /// # Errors
    /// If the port cannot be bound.
    pub fn start() -> std::io::Result<Self> {
        Self::bind("127.0.0.1:0")
    }

    /// Starts on `addr` (e.g. `127.0.0.1:8000`).
    ///
    /// # Errors
    /// If the address cannot be bound.
    pub fn bind(addr: &str) -> std::io::Result<Self> {
        let listener = TcpListener::bind(addr)?;
        let addr = listener.local_addr()?;
        let state = Arc::new(State::default());
        let shared = Arc::clone(&state);
        let acceptor = std::thread::spawn(move || {
            for stream in listener.incoming() {
                if shared.stop.load(Ordering::SeqCst) {
                    break;
                }
                if let Ok(stream) = stream {
                    let state = Arc::clone(&shared);
                    std::thread::spawn(move || {
                        // A client that hung up (timeout tests) is not the server's problem.
                        let _ = handle(stream, &state);
                    });
                }
            }
        });
        Ok(Self {
            addr,
            state,
            acceptor: Some(acceptor),
        })
    }

    /// Base URL, e.g. `http://127.0.0.1:41234`.
    #[must_use]
    pub fn url(&self) -> String {
        format!("http://{}", self.addr)
    }

    /// `POST /v1/predict` requests received so far (faulted ones included).
    #[must_use]
    pub fn predict_requests(&self) -> usize {
        self.state.predict_requests.load(Ordering::SeqCst)
    }

    /// Blocks until the server stops (it never does on its own; for the binary).
    pub fn wait(mut self) {
        if let Some(acceptor) = self.acceptor.take() {
            let _ = acceptor.join();
        }
    }
}

impl Drop for TestServer {
    fn drop(&mut self) {
        self.state.stop.store(true, Ordering::SeqCst);
        // Wake the blocking accept so the thread sees the flag.
        let _ = TcpStream::connect(self.addr);
        if let Some(acceptor) = self.acceptor.take() {
            let _ = acceptor.join();
        }
    }
}

struct Reply {
    status: u16,
    extra_headers: String,
    body: String,
}

impl Reply {
    fn json(status: u16, body: String) -> Self {
        Self {
            status,
            extra_headers: String::new(),
            body,
        }
    }
}

fn handle(stream: TcpStream, state: &State) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request_line = String::new();
    reader.read_line(&mut request_line)?;
    let mut content_length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line)? == 0 || line == "\r\n" || line == "\n" {
            break;
        }
        if let Some((name, value)) = line.split_once(':')
            && name.trim().eq_ignore_ascii_case("content-length")
        {
            content_length = value.trim().parse::<usize>().ok();
        }
    }
    let reply = if !request_line.starts_with("POST /v1/predict ") {
        Reply::json(
            404,
            r#"{"error":"only POST /v1/predict exists"}"#.to_owned(),
        )
    } else if let Some(length) = content_length.filter(|&n| n <= MAX_BODY_BYTES) {
        let mut body = vec![0; length];
        reader.read_exact(&mut body)?;
        state.predict_requests.fetch_add(1, Ordering::SeqCst);
        predict(&body, state)
    } else {
        Reply::json(411, r#"{"error":"send a Content-Length"}"#.to_owned())
    };
    let reason = match reply.status {
        200 => "OK",
        404 => "Not Found",
        411 => "Length Required",
        422 => "Unprocessable Entity",
        429 => "Too Many Requests",
        _ => "Internal Server Error",
    };
    let mut stream = stream;
    write!(
        stream,
        "HTTP/1.1 {} {reason}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n{}\r\n{}",
        reply.status,
        reply.body.len(),
        reply.extra_headers,
        reply.body
    )?;
    stream.flush()
}

enum Fault {
    TooMany,
    Internal,
    Malformed,
    Slow(u64),
}

/// The fault for the `attempt`-th request (1-based) of a sample id, if any.
fn fault_for(sample_id: &str, attempt: u32) -> Option<Fault> {
    let (_, spec) = sample_id.split_once('#')?;
    let mut seen = 0;
    for item in spec.split(',') {
        let (kind, count) = item.rsplit_once('x')?;
        seen += count.parse::<u32>().ok()?;
        if attempt <= seen {
            return match kind {
                "429" => Some(Fault::TooMany),
                "500" => Some(Fault::Internal),
                "malformed" => Some(Fault::Malformed),
                slow => slow.strip_prefix("slow")?.parse().ok().map(Fault::Slow),
            };
        }
    }
    None
}

fn predict(body: &[u8], state: &State) -> Reply {
    let request: PredictRequest = match serde_json::from_slice(body) {
        Ok(request) => request,
        Err(e) => {
            return Reply::json(
                422,
                serde_json::json!({ "error": e.to_string() }).to_string(),
            );
        }
    };
    let attempt = {
        let mut attempts = state
            .attempts_by_sample
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let n = attempts.entry(request.sample_id.clone()).or_insert(0);
        *n += 1;
        *n
    };
    match fault_for(&request.sample_id, attempt) {
        Some(Fault::TooMany) => {
            return Reply {
                status: 429,
                extra_headers: "Retry-After: 0\r\n".to_owned(),
                body: r#"{"error":"all GPU slots busy"}"#.to_owned(),
            };
        }
        Some(Fault::Internal) => {
            return Reply::json(500, r#"{"error":"injected failure"}"#.to_owned());
        }
        Some(Fault::Malformed) => {
            return Reply::json(200, r#"{"sample_id": "#.to_owned());
        }
        Some(Fault::Slow(ms)) => std::thread::sleep(Duration::from_millis(ms)),
        None => {}
    }
    let response = answer(&request);
    match serde_json::to_string(&response) {
        Ok(text) => Reply::json(200, text),
        Err(e) => Reply::json(
            500,
            serde_json::json!({ "error": e.to_string() }).to_string(),
        ),
    }
}

/// Model-frame box (min, max) and centroid of feature rows.
fn shape(rows: &[FeatureRow]) -> ([f64; 3], [f64; 3]) {
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    let mut sum = [0.0; 3];
    for row in rows {
        for k in 0..3 {
            let v = f64::from(row[3 + k]);
            min[k] = min[k].min(v);
            max[k] = max[k].max(v);
            sum[k] += v;
        }
    }
    let n = rows.len().max(1) as f64;
    let extents = [0, 1, 2].map(|k| (max[k] - min[k]).max(0.0));
    (extents, sum.map(|s| round4(s / n)))
}

fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

fn part_answer(task: Task, id: &str, rows: &[FeatureRow]) -> PartAnswer {
    let (extents, centroid) = shape(rows);
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| extents[a].total_cmp(&extents[b]));
    let (smallest, longest_axis) = (extents[order[0]], order[2]);
    let largest = extents[longest_axis];
    let ratio = if largest > 0.0 {
        smallest / largest
    } else {
        1.0
    };
    let mut answer = PartAnswer {
        id: id.to_owned(),
        ..PartAnswer::default()
    };
    match task {
        Task::Kinematics => {
            let motion = if ratio < 0.2 {
                Some(("C", [0.0, 0.25]))
            } else if ratio < 0.6 {
                Some(("B", [0.0, round4(largest / 2.0)]))
            } else {
                None
            };
            if let Some((kind, range)) = motion {
                // Unit x: theta 90, phi 0; unit y: 90, 90; unit z: 0, 0.
                let (theta, phi) = [(90.0, 0.0), (90.0, 90.0), (0.0, 0.0)][longest_axis];
                answer.motion_type = Some(kind.to_owned());
                answer.axis = Some(AxisAnswer::Spherical { theta, phi });
                answer.pivot = Some(centroid);
                answer.range = Some(range);
            }
        }
        Task::Physics => {
            answer.physical_properties = Some(PhysicsAnswer {
                material: "wood".to_owned(),
                density: 0.7,
                young: 10.0,
                hardness: 4.0,
                poisson: 0.3,
                friction: 0.45,
                affordance: Some(2),
                graspable: Some(ratio < 0.2),
            });
        }
        Task::Structure => answer.members = Some(vec![id.to_owned()]),
        Task::ObjectLevel => {}
    }
    answer
}

/// The rule-based answer to a request.
#[must_use]
pub fn answer(request: &PredictRequest) -> PredictResponse {
    let object = (request.task == Task::ObjectLevel).then(|| {
        let (extents, _) = shape(&request.object.features);
        ObjectAnswer {
            object_name: "object".to_owned(),
            category: "Other/Unknown".to_owned(),
            dimension: Some(extents.map(|e| round4(e * 50.0))),
            volume: None,
            mass: 1.0,
        }
    });
    let parts = if request.task.is_per_part() {
        request
            .parts
            .iter()
            .map(|p| part_answer(request.task, &p.id, &p.features))
            .collect()
    } else {
        Vec::new()
    };
    PredictResponse {
        sample_id: request.sample_id.clone(),
        task: request.task,
        model: format!("uniphysgen-test-server/{}", request.task),
        parts,
        object,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faults_apply_in_turn_to_the_first_requests() {
        let id = "s#429x1,500x2";
        assert!(matches!(fault_for(id, 1), Some(Fault::TooMany)));
        assert!(matches!(fault_for(id, 2), Some(Fault::Internal)));
        assert!(matches!(fault_for(id, 3), Some(Fault::Internal)));
        assert!(fault_for(id, 4).is_none());
        assert!(matches!(fault_for("s#slow50x1", 1), Some(Fault::Slow(50))));
        assert!(fault_for("plain", 1).is_none());
    }

    #[test]
    fn a_thin_panel_is_revolute_about_its_longest_axis() {
        // A 0.02 x 1 x 0.5 panel: ratio 0.02, longest axis y -> theta 90, phi 90.
        let rows: Vec<FeatureRow> = [[0.0, 0.0, 0.0], [0.02, 1.0, 0.5]]
            .iter()
            .map(|p| {
                let mut row = [0.0; 12];
                row[3..6].copy_from_slice(p);
                row
            })
            .collect();
        let answer = part_answer(Task::Kinematics, "1", &rows);
        assert_eq!(answer.motion_type.as_deref(), Some("C"));
        assert_eq!(
            answer.axis,
            Some(AxisAnswer::Spherical {
                theta: 90.0,
                phi: 90.0
            })
        );
        assert_eq!(answer.pivot, Some([0.01, 0.5, 0.25]));
    }
}
