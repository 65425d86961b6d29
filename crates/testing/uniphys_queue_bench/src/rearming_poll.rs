//! A poll strategy for apalis that never loses its wake-up.
//!
//! apalis 1.0's `PollWith` calls `PollStrategy::poll_drive` and ignores a `Ready`; its
//! `IntervalStrategy` answers `Ready` by creating the next timer without polling it, so no wake-up
//! is registered. When the fetch that follows takes longer than the interval and comes back empty,
//! the worker parks with nothing to wake it but its next heartbeat (30 s by default): on an idle
//! queue, with a 5 ms interval, a new task then waits about 30 s. This strategy polls the new timer
//! before answering `Ready`, so a wake-up is always registered.

use std::future::Future as _;
use std::pin::Pin;
use std::task::{Context, Poll};
use std::time::Duration;

use apalis::prelude::{PollSnapshot, PollStrategy};

/// Wakes the worker every `period`.
#[derive(Debug)]
pub(crate) struct RearmingInterval {
    period: Duration,
    timer: Pin<Box<tokio::time::Sleep>>,
}

impl RearmingInterval {
    pub(crate) fn new(period: Duration) -> Self {
        Self {
            period,
            timer: Box::pin(tokio::time::sleep(period)),
        }
    }
}

impl PollStrategy for RearmingInterval {
    fn poll_drive(&mut self, cx: &mut Context<'_>, _: &PollSnapshot) -> Poll<Option<()>> {
        let mut fired = false;
        while self.timer.as_mut().poll(cx).is_ready() {
            fired = true;
            let next = tokio::time::Instant::now() + self.period;
            self.timer.as_mut().reset(next);
        }
        if fired {
            Poll::Ready(Some(()))
        } else {
            Poll::Pending
        }
    }
}
