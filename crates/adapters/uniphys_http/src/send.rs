use crate::{
    AttemptReport, Failure, HttpClient, HttpError, HttpResult, Reply, RequestBuilder, RetryPolicy,
    Step,
};

impl HttpClient {
    /// Sends the request `build` makes (once per attempt) under `policy`: each answer that is
    /// 2xx goes to `read`, which returns the value or the [`Failure`] the body is (permanent
    /// unless it marks it [`Failure::transient`]); transient failures are retried, permanent
    /// ones returned. Every attempt is reported to `observe`; `jitter_key` identifies the
    /// request (for example its body).
    ///
    /// # Errors
    /// [`HttpError::Permanent`] with the failure that may not be retried, or
    /// [`HttpError::GaveUp`] with the attempt count, elapsed time and last failure.
    pub fn send_with_retry<T>(
        &self,
        policy: &RetryPolicy,
        jitter_key: &[u8],
        build: impl Fn(&reqwest::blocking::Client) -> RequestBuilder,
        mut read: impl FnMut(Reply) -> Result<T, Failure>,
        observe: impl FnMut(&AttemptReport<'_>),
    ) -> HttpResult<T> {
        policy.run(
            jitter_key,
            |attempt| {
                let outcome = self
                    .send(build(self.inner()), attempt.time_left)
                    .and_then(&mut read);
                match outcome {
                    Ok(value) => Step::Done(value),
                    Err(failure) if failure.is_transient() => Step::Retry(failure),
                    Err(failure) => Step::Stop(HttpError::Permanent { failure }),
                }
            },
            observe,
            |error| error,
        )
    }
}
