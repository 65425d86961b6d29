//! The HTTP client the OTLP exporter posts spans with: `reqwest`'s blocking client, the one HTTP
//! client of the workspace (the model clients use it too), instead of the exporter's async
//! clients and the runtime they need.
//!
//! The SDK's batch span processor exports on its own thread and drives the export future with
//! a simple executor, so a blocking call inside `send_bytes` blocks only that thread. A blocking
//! `reqwest` client may not be built inside an async runtime, and the exporter is built inside
//! the service's: the client is built on the first export, on the exporter's thread.

use std::sync::OnceLock;
use std::time::Duration;

use opentelemetry_http::{Bytes, HttpClient, HttpError, Request, Response};

/// Largest collector response read, in bytes (responses are empty or a short status).
const MAX_RESPONSE_BYTES: u64 = 1024 * 1024;

/// A blocking `reqwest` client, built on first use, behind the exporter's [`HttpClient`]
/// interface.
#[derive(Debug)]
pub(crate) struct BlockingClient {
    timeout: Duration,
    client: OnceLock<reqwest::blocking::Client>,
}

impl BlockingClient {
    /// A client whose every request (connect, send, read) ends after `timeout`.
    pub(crate) fn new(timeout: Duration) -> Self {
        Self {
            timeout,
            client: OnceLock::new(),
        }
    }

    fn client(&self) -> Result<&reqwest::blocking::Client, HttpError> {
        if let Some(client) = self.client.get() {
            return Ok(client);
        }
        let built = reqwest::blocking::Client::builder()
            .timeout(self.timeout)
            .build()?;
        Ok(self.client.get_or_init(|| built))
    }

    fn send(&self, request: Request<Bytes>) -> Result<Response<Bytes>, HttpError> {
        let (parts, body) = request.into_parts();
        let request = Request::from_parts(parts, body.to_vec());
        let request = reqwest::blocking::Request::try_from(request)?;
        // The exporter reads the status itself (and retries 429 and 5xx).
        let response = self.client()?.execute(request)?;
        let mut builder = Response::builder().status(response.status());
        for (name, value) in response.headers() {
            builder = builder.header(name, value);
        }
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(
            &mut std::io::Read::take(response, MAX_RESPONSE_BYTES),
            &mut bytes,
        )?;
        Ok(builder.body(Bytes::from(bytes))?)
    }
}

#[async_trait::async_trait]
impl HttpClient for BlockingClient {
    async fn send_bytes(&self, request: Request<Bytes>) -> Result<Response<Bytes>, HttpError> {
        self.send(request)
    }
}
