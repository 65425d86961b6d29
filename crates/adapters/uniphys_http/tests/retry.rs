//! The retry core against a tiny loopback server (`std::net`), one canned answer per
//! connection: a 429 with `Retry-After` then 200, a server that never answers, a 404.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use uniphys_http::{AttemptOutcome, FailureKind, HttpClient, HttpConfig, HttpError, RetryPolicy};

/// What the server does with one connection.
#[derive(Clone)]
enum Answer {
    /// Writes this raw HTTP response and closes.
    Raw(&'static str),
    /// Reads the request and holds the connection open without answering.
    Hang,
}

/// Serves `answers` in order (the last one repeats), one per connection; returns the base URL
/// and the arrival time of each request.
fn serve(answers: Vec<Answer>) -> (String, Arc<Mutex<Vec<Instant>>>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind loopback");
    let url = format!("http://{}", listener.local_addr().expect("address"));
    let arrivals = Arc::new(Mutex::new(Vec::new()));
    let seen = Arc::clone(&arrivals);
    std::thread::spawn(move || {
        for (index, stream) in listener.incoming().enumerate() {
            let Ok(stream) = stream else { return };
            let answer = answers[index.min(answers.len() - 1)].clone();
            let seen = Arc::clone(&seen);
            std::thread::spawn(move || answer_one(stream, &answer, &seen));
        }
    });
    (url, arrivals)
}

fn answer_one(mut stream: TcpStream, answer: &Answer, seen: &Mutex<Vec<Instant>>) {
    let mut reader = BufReader::new(stream.try_clone().expect("clone stream"));
    let mut content_length = 0;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).unwrap_or(0) == 0 {
            return;
        }
        if let Some(value) = line.to_ascii_lowercase().strip_prefix("content-length:") {
            content_length = value.trim().parse().unwrap_or(0);
        }
        if line == "\r\n" {
            break;
        }
    }
    let mut body = vec![0; content_length];
    let _ = reader.read_exact(&mut body);
    seen.lock().expect("lock").push(Instant::now());
    match answer {
        Answer::Raw(text) => {
            let _ = stream.write_all(text.as_bytes());
        }
        Answer::Hang => std::thread::sleep(Duration::from_secs(5)),
    }
}

fn client(attempt_timeout: Duration) -> HttpClient {
    HttpClient::new(HttpConfig {
        connect_timeout: Duration::from_secs(2),
        attempt_timeout,
        ..HttpConfig::default()
    })
    .expect("client")
}

/// `GET url` under `policy` with a client whose attempts time out after `attempt_timeout`; the
/// body of the 2xx answer.
fn get(policy: &RetryPolicy, attempt_timeout: Duration, url: &str) -> Result<String, HttpError> {
    client(attempt_timeout).send_with_retry(
        policy,
        b"request",
        |http| http.get(url),
        |reply| Ok(reply.body),
        |_| {},
    )
}

const TOO_MANY: &str = "HTTP/1.1 429 Too Many Requests\r\nRetry-After: 1\r\nContent-Length: 26\r\nConnection: close\r\n\r\n{\"error\":\"rate limited\"}\r\n";
const OK: &str = "HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: 11\r\nConnection: close\r\n\r\n{\"ok\":true}";
const NOT_FOUND: &str =
    "HTTP/1.1 404 Not Found\r\nContent-Length: 9\r\nConnection: close\r\n\r\nno route!";

#[test]
fn a_429_with_retry_after_is_waited_for_then_the_200_is_returned() {
    let (url, arrivals) = serve(vec![Answer::Raw(TOO_MANY), Answer::Raw(OK)]);
    let policy = RetryPolicy {
        max_attempts: 3,
        base_delay: Duration::from_millis(1),
        max_delay: Duration::from_secs(5),
        ..RetryPolicy::default()
    };
    let mut reports = Vec::new();
    let body = client(Duration::from_secs(5))
        .send_with_retry(
            &policy,
            b"request",
            |http| http.post(format!("{url}/v1/thing")).body("{}"),
            |reply| Ok(reply.body),
            |report| {
                let wait = match report.outcome {
                    AttemptOutcome::Retrying { wait, .. } => Some(wait),
                    _ => None,
                };
                reports.push((report.number, report.status(), wait));
            },
        )
        .unwrap();
    assert_eq!(body, "{\"ok\":true}");
    // Attempt 1 got the 429 and waited the server's 1 s (not the 1 ms backoff); attempt 2 won.
    assert_eq!(
        reports,
        [
            (1, Some(429), Some(Duration::from_secs(1))),
            (2, None, None)
        ]
    );
    let arrivals = arrivals.lock().unwrap();
    assert_eq!(arrivals.len(), 2);
    let gap = arrivals[1].duration_since(arrivals[0]);
    assert!(
        gap >= Duration::from_secs(1) && gap < Duration::from_secs(3),
        "{gap:?}"
    );
}

#[test]
fn a_server_that_never_answers_times_out_on_every_attempt() {
    let (url, arrivals) = serve(vec![Answer::Hang]);
    let policy = RetryPolicy {
        max_attempts: 2,
        base_delay: Duration::from_millis(10),
        ..RetryPolicy::default()
    };
    let start = Instant::now();
    let error = get(&policy, Duration::from_millis(200), &format!("{url}/slow")).unwrap_err();
    let elapsed = start.elapsed();
    let HttpError::GaveUp { attempts, last, .. } = &error else {
        panic!("{error:?}");
    };
    assert_eq!(*attempts, 2);
    assert_eq!(last.kind, FailureKind::Timeout);
    assert!(error.to_string().contains("timed out"), "{error}");
    assert!(
        elapsed >= Duration::from_millis(400) && elapsed < Duration::from_secs(3),
        "{elapsed:?}"
    );
    assert_eq!(arrivals.lock().unwrap().len(), 2);
}

#[test]
fn the_overall_deadline_cuts_an_attempt_short() {
    let (url, _arrivals) = serve(vec![Answer::Hang]);
    let policy = RetryPolicy {
        max_attempts: 5,
        deadline: Some(Duration::from_millis(300)),
        ..RetryPolicy::default()
    };
    let start = Instant::now();
    let error = get(&policy, Duration::from_secs(10), &format!("{url}/slow")).unwrap_err();
    assert!(
        matches!(
            &error,
            HttpError::GaveUp {
                attempts: 1,
                deadline_passed: true,
                ..
            }
        ),
        "{error:?}"
    );
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn a_404_is_permanent_and_not_retried() {
    let (url, arrivals) = serve(vec![Answer::Raw(NOT_FOUND), Answer::Raw(OK)]);
    let error = get(
        &RetryPolicy::default(),
        Duration::from_secs(5),
        &format!("{url}/missing"),
    )
    .unwrap_err();
    let HttpError::Permanent { failure } = &error else {
        panic!("{error:?}");
    };
    assert_eq!(
        (failure.status, failure.detail.as_str()),
        (Some(404), "no route!")
    );
    assert_eq!(arrivals.lock().unwrap().len(), 1);
}

#[test]
fn nobody_listening_is_a_transient_connect_failure() {
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let policy = RetryPolicy {
        max_attempts: 2,
        base_delay: Duration::from_millis(1),
        ..RetryPolicy::default()
    };
    let error = get(
        &policy,
        Duration::from_secs(2),
        &format!("http://127.0.0.1:{port}/"),
    )
    .unwrap_err();
    let HttpError::GaveUp { attempts, last, .. } = &error else {
        panic!("{error:?}");
    };
    assert_eq!((*attempts, last.kind), (2, FailureKind::Connect));
    assert!(error.to_string().contains("cannot reach"), "{error}");
}
