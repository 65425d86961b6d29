use serde::{Deserialize, Serialize};

/// Identifier of a part within one asset: a small integer, stable across stages.
///
/// Displays as `part_<n>`, which is also the stem of the part's mesh file in the UniPhys-40K layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct PartId(pub u32);

impl std::fmt::Display for PartId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "part_{}", self.0)
    }
}
