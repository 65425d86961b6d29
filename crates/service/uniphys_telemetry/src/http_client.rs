//! The HTTP client the OTLP exporter posts spans with: `ureq` (blocking, plain HTTP), already
//! in the workspace, instead of the exporter's reqwest or hyper clients and their trees.
//!
//! The SDK's batch span processor exports on its own thread and drives the export future with
//! a simple executor, so a blocking call inside `send_bytes` blocks only that thread.

use std::time::Duration;

use opentelemetry_http::{Bytes, HttpClient, HttpError, Request, Response};

/// Largest collector response read, in bytes (responses are empty or a short status).
const MAX_RESPONSE_BYTES: u64 = 1024 * 1024;

/// A blocking `ureq` agent behind the exporter's [`HttpClient`] interface.
#[derive(Debug)]
pub(crate) struct UreqClient {
    agent: ureq::Agent,
}

impl UreqClient {
    /// A client whose every request (connect, send, read) ends after `timeout`.
    pub(crate) fn new(timeout: Duration) -> Self {
        let config = ureq::Agent::config_builder()
            .timeout_global(Some(timeout))
            // The exporter reads the status itself (and retries 429 and 5xx).
            .http_status_as_error(false)
            .build();
        Self {
            agent: ureq::Agent::new_with_config(config),
        }
    }

    fn send(&self, request: Request<Bytes>) -> Result<Response<Bytes>, HttpError> {
        let (parts, body) = request.into_parts();
        let request = Request::from_parts(parts, &body[..]);
        let response = self.agent.run(request)?;
        let (parts, mut body) = response.into_parts();
        let bytes = body.with_config().limit(MAX_RESPONSE_BYTES).read_to_vec()?;
        Ok(Response::from_parts(parts, Bytes::from(bytes)))
    }
}

#[async_trait::async_trait]
impl HttpClient for UreqClient {
    async fn send_bytes(&self, request: Request<Bytes>) -> Result<Response<Bytes>, HttpError> {
        self.send(request)
    }
}
