use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Outcome of one check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckOutcome {
    /// The check ran and held.
    Pass,
    /// The check ran and did not hold; the asset is not valid as is.
    Fail,
    /// The check ran and found something worth a look that does not invalidate the asset.
    Warn,
    /// The check did not apply.
    Skipped,
}

/// One check on one subject (a part, a joint, or the object).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckResult {
    /// Check name, e.g. `inertia_positive_definite`.
    pub check: String,
    /// What was checked, e.g. `part_2` or `joint door_hinge` or `object`.
    pub subject: String,
    /// Outcome.
    pub outcome: CheckOutcome,
    /// Human-readable explanation.
    pub message: String,
}

/// A named group of checks (e.g. `export`, `intrinsic`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReportSection {
    /// Section name.
    pub name: String,
    /// The checks, in the order they ran.
    pub checks: Vec<CheckResult>,
}

impl ReportSection {
    /// Whether no check in the section failed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.checks.iter().all(|c| c.outcome != CheckOutcome::Fail)
    }
}

/// The verification report of an asset: sections of checks and an overall verdict.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct VerificationReport {
    /// Sections, in the order they ran.
    pub sections: Vec<ReportSection>,
    /// The numbers behind the checks: by subject (e.g. `joint hinge_door`), then by metric name
    /// (names carry their unit, e.g. `max_penetration_growth_m`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub metrics: BTreeMap<String, BTreeMap<String, f64>>,
}

impl VerificationReport {
    /// Whether every section passed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.sections.iter().all(ReportSection::passed)
    }

    /// All failed checks, in order.
    pub fn failures(&self) -> impl Iterator<Item = &CheckResult> {
        self.sections
            .iter()
            .flat_map(|s| s.checks.iter())
            .filter(|c| c.outcome == CheckOutcome::Fail)
    }
}
