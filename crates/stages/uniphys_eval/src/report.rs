//! The serialisable per-task report.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Report of one evaluation task: paper metrics, counts and extra metrics.
///
/// A metric is `None` when no valid pair contributed to it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TaskReport {
    /// The metrics reported in the paper, by name.
    pub paper_metrics: BTreeMap<String, Option<f64>>,
    /// Counts of records and of valid pairs per metric, by name.
    pub counts: BTreeMap<String, u64>,
    /// Additional metrics not in the paper, by name.
    pub extra_metrics: BTreeMap<String, Option<f64>>,
}

impl TaskReport {
    /// A paper metric by name (`None` if absent or without valid pairs).
    #[must_use]
    pub fn paper(&self, name: &str) -> Option<f64> {
        self.paper_metrics.get(name).copied().flatten()
    }

    /// An extra metric by name (`None` if absent or without valid pairs).
    #[must_use]
    pub fn extra(&self, name: &str) -> Option<f64> {
        self.extra_metrics.get(name).copied().flatten()
    }

    /// A count by name (0 if absent).
    #[must_use]
    pub fn count(&self, name: &str) -> u64 {
        self.counts.get(name).copied().unwrap_or(0)
    }

    pub(crate) fn set_paper(&mut self, name: &str, value: Option<f64>) {
        self.paper_metrics.insert(name.to_owned(), value);
    }

    pub(crate) fn set_extra(&mut self, name: &str, value: Option<f64>) {
        self.extra_metrics.insert(name.to_owned(), value);
    }

    pub(crate) fn set_count(&mut self, name: &str, value: u64) {
        self.counts.insert(name.to_owned(), value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_serialises_missing_metric_as_null_and_keeps_sections() {
        let mut report = TaskReport::default();
        report.set_paper("a", Some(0.5));
        report.set_paper("b", None);
        report.set_count("records", 3);
        report.set_extra("c", Some(1.0));
        let json = serde_json::to_value(&report).expect("serialises");
        assert_eq!(json["paper_metrics"]["a"], 0.5);
        assert!(json["paper_metrics"]["b"].is_null());
        assert_eq!(json["counts"]["records"], 3);
        assert_eq!(json["extra_metrics"]["c"], 1.0);
        assert_eq!(report.paper("b"), None);
        assert_eq!(report.count("missing"), 0);
    }
}
