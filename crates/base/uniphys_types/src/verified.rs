//! What verification decided about a grounded asset, kept between the queue's `verify` stage
//! (sweeps, corrections, the dynamic check: the CPU-heaviest checks) and `convert`, which exports
//! it: a retried export verifies nothing again.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::{AssetRecord, PartId, ReportSection, TypesError, TypesResult};

/// Version of [`VerifiedAsset`] written by this build; a reader refuses others.
pub const VERIFIED_VERSION: u32 = 1;

/// A verified asset: the grounded record with the joints verification corrected, the report's
/// verification sections and their numbers, and what the export needs of the checks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerifiedAsset {
    /// [`VERIFIED_VERSION`] when written by this build.
    pub version: u32,
    /// The record after verification (corrected joints replaced), in the grounded frame.
    pub record: AssetRecord,
    /// Sections `intrinsic`, `articulation` and `dynamics` of the report.
    pub sections: Vec<ReportSection>,
    /// The numbers behind the checks, by subject then metric (the report's `metrics`).
    pub metrics: BTreeMap<String, BTreeMap<String, f64>>,
    /// One line per corrected joint (the export's notes).
    pub corrections: Vec<String>,
    /// Pairs of parts touching at rest (the dynamic check ignored their contacts; the MJCF
    /// excludes them).
    pub touching: Vec<(PartId, PartId)>,
    /// Movable joints swept, and how many passed their sweep as grounded.
    pub joints_swept: usize,
    /// See `joints_swept`.
    pub joints_passed: usize,
    /// Whether the intrinsic checks (levels 0-4) passed.
    pub intrinsic_passed: bool,
}

impl VerifiedAsset {
    /// `self` when it is of this build's version, its record keeps its invariants and its
    /// touching pairs name its parts (a value read back from the store).
    pub fn checked(self) -> TypesResult<Self> {
        if self.version != VERIFIED_VERSION {
            return Err(TypesError::Unreadable(format!(
                "verified asset of version {}, this build reads version {VERIFIED_VERSION}",
                self.version
            )));
        }
        self.record.validate()?;
        let parts = self.record.parts.len();
        if let Some((a, b)) = self
            .touching
            .iter()
            .find(|(a, b)| a.0 as usize >= parts || b.0 as usize >= parts)
        {
            return Err(TypesError::Unreadable(format!(
                "verified asset with touching parts {} and {} of {parts} parts",
                a.0, b.0
            )));
        }
        Ok(self)
    }
}
