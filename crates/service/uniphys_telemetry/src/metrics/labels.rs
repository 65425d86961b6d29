//! Label sets of the metric families, and the bounded set of stage outcomes.

use prometheus_client::encoding::EncodeLabelSet;

/// How one attempt of a stage run ended, as the worker saw it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StageOutcome {
    /// Completed; its output is recorded.
    Succeeded,
    /// Failed; a retry is scheduled.
    Retrying,
    /// Failed for good (permanent failure or attempts used up): dead-lettered.
    Dead,
    /// The lease was lost (expired or superseded) before the worker finished.
    LeaseLost,
    /// The job was cancelled while the stage ran.
    Cancelled,
}

impl StageOutcome {
    /// The label value: `succeeded`, `retrying`, `dead`, `lease_lost` or `cancelled`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Succeeded => "succeeded",
            Self::Retrying => "retrying",
            Self::Dead => "dead",
            Self::LeaseLost => "lease_lost",
            Self::Cancelled => "cancelled",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct StageLabels {
    pub stage: String,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct StageStateLabels {
    pub stage: String,
    pub state: &'static str,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct StageOutcomeLabels {
    pub stage: String,
    pub outcome: &'static str,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct TableLabels {
    pub table: String,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct HttpLabels {
    pub method: String,
    pub route: String,
    pub status: u16,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct HttpRouteLabels {
    pub method: String,
    pub route: String,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, EncodeLabelSet)]
pub(super) struct OpLabels {
    pub op: String,
}
