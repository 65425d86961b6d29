use std::time::{Duration, Instant};

use crate::{Failure, HttpError, RetryPolicy};

/// The attempt about to be made, as [`RetryPolicy::run`] hands it to the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Attempt {
    /// 1-based attempt number.
    pub number: u32,
    /// Whether no further attempt is allowed after this one (`max_attempts` reached; the
    /// deadline may still end the retries earlier).
    pub is_last: bool,
    /// Time left before the policy's deadline (`None` without a deadline): the longest this
    /// attempt may take.
    pub time_left: Option<Duration>,
}

/// What one attempt came to, as judged by the caller.
#[derive(Debug)]
pub enum Step<T, E> {
    /// Success: the loop returns it.
    Done(T),
    /// A transient failure: retried while the policy allows.
    Retry(Failure),
    /// A permanent failure (or the caller's own reason to stop): returned at once.
    Stop(E),
}

/// How one attempt ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AttemptOutcome<'a> {
    /// It succeeded.
    Succeeded,
    /// It failed permanently (or the caller stopped).
    Stopped,
    /// It failed transiently; the next attempt follows after `wait`.
    Retrying {
        /// What went wrong.
        failure: &'a Failure,
        /// The wait before the next attempt.
        wait: Duration,
    },
    /// It failed transiently and no attempt follows (attempts or deadline spent).
    GaveUp {
        /// What went wrong.
        failure: &'a Failure,
    },
}

/// One attempt, reported to the caller's callback (to log it or count it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttemptReport<'a> {
    /// 1-based attempt number.
    pub number: u32,
    /// Time from the start of the first attempt to the end of this one.
    pub elapsed: Duration,
    /// How it ended.
    pub outcome: AttemptOutcome<'a>,
}

impl AttemptReport<'_> {
    /// The HTTP status of a failed attempt's answer, if one came.
    #[must_use]
    pub fn status(&self) -> Option<u16> {
        match self.outcome {
            AttemptOutcome::Retrying { failure, .. } | AttemptOutcome::GaveUp { failure } => {
                failure.status
            }
            AttemptOutcome::Succeeded | AttemptOutcome::Stopped => None,
        }
    }
}

impl RetryPolicy {
    /// The retry loop: calls `attempt` until it is [`Step::Done`] or [`Step::Stop`], or until
    /// a [`Step::Retry`] may not be retried (`max_attempts` made, or the wait would pass the
    /// deadline), sleeping [`RetryPolicy::delay`] between attempts (keyed on `jitter_key`, the
    /// request's identity). Every attempt is reported to `observe`. Giving up is an
    /// [`HttpError::GaveUp`] (attempts, elapsed time, the last failure) that `gave_up` turns
    /// into the caller's error.
    ///
    /// # Errors
    /// The [`Step::Stop`] error, or `gave_up`'s.
    pub fn run<T, E>(
        &self,
        jitter_key: &[u8],
        mut attempt: impl FnMut(&Attempt) -> Step<T, E>,
        mut observe: impl FnMut(&AttemptReport<'_>),
        gave_up: impl FnOnce(HttpError) -> E,
    ) -> Result<T, E> {
        let start = Instant::now();
        let mut number = 1;
        loop {
            let time_left = self
                .deadline
                .map(|deadline| deadline.saturating_sub(start.elapsed()));
            let step = attempt(&Attempt {
                number,
                is_last: number >= self.max_attempts,
                time_left,
            });
            let report = |outcome| AttemptReport {
                number,
                elapsed: start.elapsed(),
                outcome,
            };
            let failure = match step {
                Step::Done(value) => {
                    observe(&report(AttemptOutcome::Succeeded));
                    return Ok(value);
                }
                Step::Stop(error) => {
                    observe(&report(AttemptOutcome::Stopped));
                    return Err(error);
                }
                Step::Retry(failure) => failure,
            };
            let wait = self.delay(number, jitter_key, failure.retry_after);
            let deadline_passed = self
                .deadline
                .is_some_and(|deadline| start.elapsed() + wait >= deadline);
            if number >= self.max_attempts || deadline_passed {
                observe(&report(AttemptOutcome::GaveUp { failure: &failure }));
                return Err(gave_up(HttpError::GaveUp {
                    attempts: number,
                    elapsed: start.elapsed(),
                    deadline_passed: deadline_passed && number < self.max_attempts,
                    last: failure,
                }));
            }
            observe(&report(AttemptOutcome::Retrying {
                failure: &failure,
                wait,
            }));
            std::thread::sleep(wait);
            number += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FailureKind;

    const MS: Duration = Duration::from_millis(1);

    fn policy(max_attempts: u32) -> RetryPolicy {
        RetryPolicy {
            max_attempts,
            base_delay: MS,
            max_delay: MS * 4,
            ..RetryPolicy::default()
        }
    }

    fn refused() -> Failure {
        Failure::new(FailureKind::Connect, "refused")
    }

    #[test]
    fn transient_failures_are_retried_until_success_and_reported() {
        let mut reports = Vec::new();
        let result: Result<u32, HttpError> = policy(4).run(
            b"k",
            |attempt| {
                if attempt.number < 3 {
                    Step::Retry(refused())
                } else {
                    Step::Done(attempt.number)
                }
            },
            |report| reports.push((report.number, report.outcome == AttemptOutcome::Succeeded)),
            |error| error,
        );
        assert_eq!(result.unwrap(), 3);
        assert_eq!(reports, [(1, false), (2, false), (3, true)]);
    }

    #[test]
    fn attempts_run_out_with_the_last_failure() {
        let mut last_flags = Vec::new();
        let error = policy(3)
            .run(
                b"k",
                |attempt| -> Step<(), HttpError> {
                    last_flags.push(attempt.is_last);
                    Step::Retry(Failure::status(503, "busy", None))
                },
                |_| {},
                |error| error,
            )
            .unwrap_err();
        let HttpError::GaveUp {
            attempts,
            last,
            deadline_passed,
            ..
        } = &error
        else {
            panic!("{error}");
        };
        assert_eq!((*attempts, *deadline_passed), (3, false));
        assert_eq!(last.status, Some(503));
        assert_eq!(last_flags, [false, false, true]);
        assert!(error.to_string().contains("HTTP 503: busy"), "{error}");
    }

    #[test]
    fn a_stop_ends_at_once() {
        let mut calls = 0;
        let error = policy(5)
            .run(
                b"k",
                |_| -> Step<(), &str> {
                    calls += 1;
                    Step::Stop("refused for good")
                },
                |_| {},
                |_| "gave up",
            )
            .unwrap_err();
        assert_eq!((error, calls), ("refused for good", 1));
    }

    #[test]
    fn the_deadline_stops_retries_whose_wait_would_pass_it() {
        let policy = RetryPolicy {
            max_attempts: 100,
            base_delay: MS * 40,
            max_delay: MS * 40,
            jitter_fraction: 0.0,
            deadline: Some(MS * 100),
        };
        let mut times_left = Vec::new();
        let error = policy
            .run(
                b"k",
                |attempt| -> Step<(), HttpError> {
                    times_left.push(attempt.time_left.unwrap());
                    Step::Retry(refused())
                },
                |_| {},
                |error| error,
            )
            .unwrap_err();
        // Attempts at about 0, 40 and 80 ms; the wait after the third would pass 100 ms.
        assert!(
            matches!(
                error,
                HttpError::GaveUp {
                    attempts: 3,
                    deadline_passed: true,
                    ..
                }
            ),
            "{error:?}"
        );
        assert!(times_left.windows(2).all(|w| w[1] < w[0]), "{times_left:?}");
        assert!(times_left[0] <= MS * 100);
    }

    #[test]
    fn a_retry_after_wait_is_used_and_reported() {
        let mut waits = Vec::new();
        let _: Result<(), HttpError> = policy(2).run(
            b"k",
            |attempt| {
                if attempt.number == 1 {
                    Step::Retry(Failure::status(429, "slow down", Some(MS * 3)))
                } else {
                    Step::Done(())
                }
            },
            |report| {
                if let AttemptOutcome::Retrying { wait, .. } = report.outcome {
                    waits.push((wait, report.status()));
                }
            },
            |error| error,
        );
        assert_eq!(waits, [(MS * 3, Some(429))]);
    }
}
