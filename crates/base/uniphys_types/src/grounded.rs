//! What grounding decided about an asset, kept between the queue's `ground` stage, which may call
//! an LVLM or a UniPhysGen server, and the stages after it, which verify and export without
//! calling them again.

use serde::{Deserialize, Serialize};

use crate::{AssetRecord, TypesError, TypesResult};

/// Version of [`GroundedAsset`] written by this build; a reader refuses others.
pub const GROUNDED_VERSION: u32 = 1;

/// A grounded asset: its record before verification (parts with their properties and masses,
/// joints as the grounders chose them), the notes grounding wrote for the report, and each
/// part's convex colliders (what verification sweeps and the export writes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroundedAsset {
    /// [`GROUNDED_VERSION`] when written by this build.
    pub version: u32,
    /// The record, in the object frame of the asset resting on the ground (z = 0).
    pub record: AssetRecord,
    /// What grounding did and why, in order (the export's notes).
    pub notes: Vec<String>,
    /// Each part's convex hulls, by part position, in the same frame.
    pub colliders: Vec<Vec<Hull>>,
}

/// A convex hull: a closed triangle mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hull {
    /// Vertex positions, metres.
    pub positions_m: Vec<[f64; 3]>,
    /// Triangles, as indices into `positions_m`.
    pub triangles: Vec<[u32; 3]>,
}

impl GroundedAsset {
    /// A grounded asset of this build's version.
    #[must_use]
    pub fn new(record: AssetRecord, notes: Vec<String>, colliders: Vec<Vec<Hull>>) -> Self {
        Self {
            version: GROUNDED_VERSION,
            record,
            notes,
            colliders,
        }
    }

    /// `self` when it is of this build's version and its record keeps its invariants (a value
    /// read back from the store).
    pub fn checked(self) -> TypesResult<Self> {
        if self.version != GROUNDED_VERSION {
            return Err(TypesError::Unreadable(format!(
                "grounded asset of version {}, this build reads version {GROUNDED_VERSION}",
                self.version
            )));
        }
        self.record.validate()?;
        if self.colliders.len() != self.record.parts.len() {
            return Err(TypesError::Unreadable(format!(
                "grounded asset with colliders for {} parts and {} parts",
                self.colliders.len(),
                self.record.parts.len()
            )));
        }
        Ok(self)
    }
}
