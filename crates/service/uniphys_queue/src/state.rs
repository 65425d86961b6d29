//! The state machines of stage runs and jobs, as stored in the `state` columns.
//!
//! ```text
//! stage run:  blocked ──deps done──► ready ──claim──► running ──complete──► succeeded
//!                                      ▲                 │
//!                                      └─fail (backoff)──┤──fail, attempts used up──► dead ──retry──► ready
//!                                                        └─lease expired: recovered like a failure
//!             blocked | ready | running ──cancel job──► cancelled ──retry──► ready
//!                                                                  (blocked while a dependency is unfinished)
//! job:        running ──all stages succeeded──► succeeded
//!             running ──a stage dead──► dead ──retry──► running
//!             running | dead ──cancel──► cancelled ──retry──► running
//! ```

use std::fmt;

use crate::{QueueError, QueueResult};

macro_rules! string_enum {
    ($(#[$doc:meta])* $name:ident { $($(#[$vdoc:meta])* $variant:ident => $text:literal),+ $(,)? }) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum $name {
            $($(#[$vdoc])* $variant),+
        }

        impl $name {
            /// The stored form.
            #[must_use]
            pub fn as_str(self) -> &'static str {
                match self {
                    $(Self::$variant => $text),+
                }
            }

            /// Parses the stored form.
            pub fn parse(text: &str) -> QueueResult<Self> {
                match text {
                    $($text => Ok(Self::$variant),)+
                    other => Err(QueueError::CorruptRow(format!(
                        "unknown {} {other:?}",
                        stringify!($name)
                    ))),
                }
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

string_enum!(
    /// Where a stage run is in its life.
    StageState {
        /// Waits for upstream stages of its job.
        Blocked => "blocked",
        /// Claimable once `run_after_ms` has passed (a retry waits here for its backoff).
        Ready => "ready",
        /// Leased by a worker until `lease_expires_at_ms`.
        Running => "running",
        /// Finished with an output manifest.
        Succeeded => "succeeded",
        /// Dead-lettered: attempts used up or a permanent failure; the error history is kept.
        Dead => "dead",
        /// Its job was cancelled.
        Cancelled => "cancelled",
    }
);

string_enum!(
    /// Where a job is in its life.
    JobState {
        /// Some stage still has work to do.
        Running => "running",
        /// Every stage succeeded.
        Succeeded => "succeeded",
        /// A stage was dead-lettered; other branches may still finish; `retry` resumes it.
        Dead => "dead",
        /// Cancelled by a user; its unfinished stages were cancelled.
        Cancelled => "cancelled",
    }
);

impl StageState {
    /// Returns whether no transition leaves this state except an explicit retry.
    #[must_use]
    pub fn is_terminal(self) -> bool {
        matches!(self, Self::Succeeded | Self::Dead | Self::Cancelled)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_round_trip_through_their_stored_form() {
        for s in [
            StageState::Blocked,
            StageState::Ready,
            StageState::Running,
            StageState::Succeeded,
            StageState::Dead,
            StageState::Cancelled,
        ] {
            assert_eq!(StageState::parse(s.as_str()).ok(), Some(s));
        }
        assert_eq!(JobState::parse("dead").ok(), Some(JobState::Dead));
        assert!(JobState::parse("Dead").is_err());
    }
}
