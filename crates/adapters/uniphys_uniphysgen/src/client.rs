use std::sync::Arc;
use std::time::Duration;

use uniphys_http::{
    Failure, FailureKind, HttpClient, HttpConfig, HttpError, RetryPolicy, Step, excerpt,
};

use crate::contract::{
    CloudInput, ObjectAnswer, PREDICT_PATH, PartAnswer, PartInput, PartPosition, PredictRequest,
    PredictResponse, Task,
};
use crate::slots::SlotGuard;
use crate::{LocalSlots, ModelInputs, SlotLimiter, UniPhysGenError, UniPhysGenResult};

/// Largest response body the client reads (answers are a few kB per part).
const MAX_RESPONSE_BYTES: u64 = 16 * 1024 * 1024;

/// Settings of a [`UniPhysGenClient`].
#[derive(Debug, Clone, PartialEq)]
pub struct ClientConfig {
    /// Server base URL, e.g. `http://gpu-1:8000` (the client posts to `<base>/v1/predict`).
    pub base_url: String,
    /// Limit on one HTTP attempt, connect to last byte. A timed-out attempt is retried like any
    /// transient failure (the shared policy); the GPU slot is released during the wait.
    pub timeout: Duration,
    /// Attempts per request, the first included (connect errors, timeouts, 408, 425, 429, 500,
    /// 502, 503 and 504 are retried).
    pub max_attempts: u32,
    /// Wait before the second attempt; doubled for each further one (less up to half of it,
    /// jitter).
    pub initial_backoff: Duration,
    /// Longest wait between attempts; also caps a server's `Retry-After`.
    pub max_backoff: Duration,
    /// Most parts in one request; more parts are split over several requests.
    pub max_parts_per_request: usize,
    /// Longest wait for a GPU slot before an attempt.
    pub slot_wait: Duration,
}

impl Default for ClientConfig {
    fn default() -> Self {
        Self {
            base_url: "http://127.0.0.1:8000".to_owned(),
            timeout: Duration::from_secs(300),
            max_attempts: 4,
            initial_backoff: Duration::from_millis(500),
            max_backoff: Duration::from_secs(30),
            max_parts_per_request: 8,
            slot_wait: Duration::from_secs(600),
        }
    }
}

/// The answers of one model for the parts asked about.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PartAnswers {
    /// Checkpoint that answered.
    pub model: String,
    /// One answer per part, in the order of [`ModelInputs::parts`].
    pub parts: Vec<PartAnswer>,
}

/// Blocking client of a UniPhysGen model server (`proto/uniphysgen/v1`): retries with
/// exponential backoff, batches parts, and takes a GPU slot around each attempt.
pub struct UniPhysGenClient {
    config: ClientConfig,
    http: HttpClient,
    policy: RetryPolicy,
    limiter: Arc<dyn SlotLimiter>,
}

impl std::fmt::Debug for UniPhysGenClient {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("UniPhysGenClient")
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

impl UniPhysGenClient {
    /// A client with its own in-process limit of `slots` concurrent requests.
    ///
    /// # Errors
    /// [`UniPhysGenError::InvalidOption`] for a zero `max_attempts` or `max_parts_per_request`.
    pub fn new(config: ClientConfig, slots: usize) -> UniPhysGenResult<Self> {
        Self::with_limiter(config, Arc::new(LocalSlots::new(slots)))
    }

    /// A client sharing `limiter` (for example a limiter across workers).
    ///
    /// # Errors
    /// [`UniPhysGenError::InvalidOption`] for a zero `max_attempts` or `max_parts_per_request`.
    pub fn with_limiter(
        config: ClientConfig,
        limiter: Arc<dyn SlotLimiter>,
    ) -> UniPhysGenResult<Self> {
        if config.max_attempts == 0 {
            return Err(UniPhysGenError::InvalidOption {
                name: "max_attempts",
                value: "0".to_owned(),
                expected: "at least 1",
            });
        }
        if config.max_parts_per_request == 0 {
            return Err(UniPhysGenError::InvalidOption {
                name: "max_parts_per_request",
                value: "0".to_owned(),
                expected: "at least 1",
            });
        }
        let http = HttpClient::new(HttpConfig {
            connect_timeout: config.timeout,
            attempt_timeout: config.timeout,
            max_response_bytes: MAX_RESPONSE_BYTES,
            user_agent: "uniphys-uniphysgen".to_owned(),
            ..HttpConfig::default()
        })
        .map_err(|error| UniPhysGenError::InvalidOption {
            name: "timeout",
            value: format!("{:?}", config.timeout),
            expected: match error {
                HttpError::InvalidOption { expected, .. } => expected,
                _ => "settings the HTTP client accepts",
            },
        })?;
        let policy = RetryPolicy::exponential(
            config.max_attempts,
            config.initial_backoff,
            config.max_backoff,
        );
        Ok(Self {
            config,
            http,
            policy,
            limiter,
        })
    }

    /// The settings.
    #[must_use]
    pub fn config(&self) -> &ClientConfig {
        &self.config
    }

    /// Asks a per-part task about every part of `inputs`, `max_parts_per_request` parts per
    /// request (so `ceil(parts / max)` requests). The structure task also gets every part's
    /// position.
    ///
    /// # Errors
    /// Transport, timeout, refusal and malformed-response errors naming the task and sample.
    pub fn predict_parts(
        &self,
        task: Task,
        sample_id: &str,
        inputs: &ModelInputs,
    ) -> UniPhysGenResult<PartAnswers> {
        let positions: Vec<PartPosition> = inputs
            .parts
            .iter()
            .zip(&inputs.part_centers_in_model)
            .map(|((id, _), c)| PartPosition {
                id: id.clone(),
                position: c.to_array().map(round4),
            })
            .collect();
        let with_positions = task == Task::Structure;
        let mut model = String::new();
        let mut answers = Vec::with_capacity(inputs.parts.len());
        for (chunk_index, chunk) in inputs
            .parts
            .chunks(self.config.max_parts_per_request)
            .enumerate()
        {
            let first = chunk_index * self.config.max_parts_per_request;
            let parts = chunk
                .iter()
                .enumerate()
                .map(|(k, (id, features))| PartInput {
                    id: id.clone(),
                    features: features.clone(),
                    position: with_positions.then(|| positions[first + k].position),
                })
                .collect();
            let request = PredictRequest {
                task,
                sample_id: sample_id.to_owned(),
                num_bins: inputs.num_bins,
                object: CloudInput {
                    features: inputs.object.clone(),
                },
                parts,
                part_list: if with_positions {
                    positions.clone()
                } else {
                    Vec::new()
                },
            };
            let response = self.predict(&request)?;
            let malformed = |reason: String| UniPhysGenError::MalformedResponse {
                task: task.to_string(),
                sample_id: sample_id.to_owned(),
                reason,
            };
            for (id, _) in chunk {
                let mut matching = response.parts.iter().filter(|a| &a.id == id);
                let answer = matching
                    .next()
                    .ok_or_else(|| malformed(format!("no answer for part {id:?}")))?;
                if matching.next().is_some() {
                    return Err(malformed(format!("two answers for part {id:?}")));
                }
                answers.push(answer.clone());
            }
            model = response.model;
        }
        Ok(PartAnswers {
            model,
            parts: answers,
        })
    }

    /// Asks the `object_level` task about the object; returns the model name and its answer.
    ///
    /// # Errors
    /// Transport, timeout, refusal and malformed-response errors naming the task and sample.
    pub fn predict_object(
        &self,
        sample_id: &str,
        inputs: &ModelInputs,
    ) -> UniPhysGenResult<(String, ObjectAnswer)> {
        let request = PredictRequest {
            task: Task::ObjectLevel,
            sample_id: sample_id.to_owned(),
            num_bins: inputs.num_bins,
            object: CloudInput {
                features: inputs.object.clone(),
            },
            parts: Vec::new(),
            part_list: Vec::new(),
        };
        let response = self.predict(&request)?;
        let object = response
            .object
            .ok_or_else(|| UniPhysGenError::MalformedResponse {
                task: Task::ObjectLevel.to_string(),
                sample_id: sample_id.to_owned(),
                reason: "the response has no \"object\" answer".to_owned(),
            })?;
        Ok((response.model, object))
    }

    /// Sends one request under the shared retry policy (connect errors, timeouts, 408, 425,
    /// 429, 500, 502, 503 and 504 retried with jittered exponential backoff, or the server's
    /// `Retry-After` on 429/503), taking a GPU slot around each attempt, and checks that the
    /// answer is for this task and sample.
    ///
    /// # Errors
    /// [`UniPhysGenError::GaveUp`], [`UniPhysGenError::Timeout`] (every attempt allowed, the
    /// last one timed out), [`UniPhysGenError::Refused`],
    /// [`UniPhysGenError::MalformedResponse`] or [`UniPhysGenError::NoSlot`].
    pub fn predict(&self, request: &PredictRequest) -> UniPhysGenResult<PredictResponse> {
        let body = serde_json::to_vec(request).map_err(|error| UniPhysGenError::InvalidOption {
            name: "request",
            value: error.to_string(),
            expected: "a request that encodes as JSON",
        })?;
        let url = format!(
            "{}{PREDICT_PATH}",
            self.config.base_url.trim_end_matches('/')
        );
        let answer = self.policy.run(
            &body,
            |attempt| {
                let _slot = match SlotGuard::take(self.limiter.as_ref(), self.config.slot_wait) {
                    Ok(slot) => slot,
                    Err(error) => return Step::Stop(error),
                };
                let http_request = self
                    .http
                    .inner()
                    .post(&url)
                    .header("content-type", "application/json")
                    .body(body.clone());
                match self.http.send(http_request, attempt.time_left) {
                    Ok(reply) => Step::Done(reply.body),
                    Err(failure) if failure.is_transient() => Step::Retry(failure),
                    Err(failure) => Step::Stop(self.refused(request, failure)),
                }
            },
            |_| {},
            |error| self.gave_up(request, error),
        )?;
        self.parse(request, &answer)
    }

    /// The error of a failure retrying would not change.
    fn refused(&self, request: &PredictRequest, failure: Failure) -> UniPhysGenError {
        match (failure.kind, failure.status) {
            (FailureKind::Status, Some(status)) => UniPhysGenError::Refused {
                task: request.task.to_string(),
                sample_id: request.sample_id.clone(),
                status,
                body: excerpt(&failure.detail, 200),
            },
            _ => UniPhysGenError::MalformedResponse {
                task: request.task.to_string(),
                sample_id: request.sample_id.clone(),
                reason: failure.to_string(),
            },
        }
    }

    /// The error of a request that ran out of attempts: a timeout if the last attempt timed
    /// out, else what the last failure was.
    fn gave_up(&self, request: &PredictRequest, error: HttpError) -> UniPhysGenError {
        match error {
            HttpError::GaveUp { last, .. } if last.kind == FailureKind::Timeout => {
                UniPhysGenError::Timeout {
                    task: request.task.to_string(),
                    sample_id: request.sample_id.clone(),
                    timeout: self.config.timeout,
                }
            }
            HttpError::GaveUp { attempts, last, .. } => UniPhysGenError::GaveUp {
                task: request.task.to_string(),
                sample_id: request.sample_id.clone(),
                attempts,
                reason: last.to_string(),
            },
            other => UniPhysGenError::GaveUp {
                task: request.task.to_string(),
                sample_id: request.sample_id.clone(),
                attempts: 0,
                reason: other.to_string(),
            },
        }
    }

    fn parse(&self, request: &PredictRequest, body: &str) -> UniPhysGenResult<PredictResponse> {
        let malformed = |reason: String| UniPhysGenError::MalformedResponse {
            task: request.task.to_string(),
            sample_id: request.sample_id.clone(),
            reason,
        };
        let response: PredictResponse = serde_json::from_str(body)
            .map_err(|e| malformed(format!("not a valid response JSON ({e})")))?;
        if response.sample_id != request.sample_id {
            return Err(malformed(format!(
                "it answers sample {:?}",
                response.sample_id
            )));
        }
        if response.task != request.task {
            return Err(malformed(format!("it answers task {}", response.task)));
        }
        Ok(response)
    }
}

fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backoff_doubles_is_capped_and_honours_retry_after() {
        let config = ClientConfig {
            initial_backoff: Duration::from_millis(100),
            max_backoff: Duration::from_millis(1000),
            ..ClientConfig::default()
        };
        let client = UniPhysGenClient::new(config, 1).unwrap();
        let policy = &client.policy;
        assert_eq!(policy.backoff_ceiling(1), Duration::from_millis(100));
        assert_eq!(policy.backoff_ceiling(3), Duration::from_millis(400));
        assert_eq!(policy.backoff_ceiling(5), Duration::from_millis(1000));
        assert_eq!(
            policy.delay(1, b"k", Some(Duration::from_millis(700))),
            Duration::from_millis(700)
        );
        assert_eq!(
            policy.delay(1, b"k", Some(Duration::from_secs(60))),
            Duration::from_millis(1000)
        );
    }

    #[test]
    fn zero_attempts_or_zero_parts_per_request_are_refused() {
        let zero_attempts = ClientConfig {
            max_attempts: 0,
            ..ClientConfig::default()
        };
        assert!(UniPhysGenClient::new(zero_attempts, 1).is_err());
        let zero_parts = ClientConfig {
            max_parts_per_request: 0,
            ..ClientConfig::default()
        };
        assert!(UniPhysGenClient::new(zero_parts, 1).is_err());
    }

    #[test]
    fn positions_round_to_four_decimals() {
        assert_eq!(round4(1.234_56), 1.2346);
        assert_eq!(round4(-0.000_04), -0.0);
    }
}
