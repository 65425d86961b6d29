use crate::PartId;

/// Errors raised when domain values break their invariants.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TypesError {
    /// A value that must be finite was NaN or infinite.
    #[error("{field} must be finite, got {value}")]
    NotFinite {
        /// Name of the offending field.
        field: &'static str,
        /// The value received.
        value: f64,
    },
    /// A value was outside its physically meaningful range.
    #[error("{field} must be in {expected}, got {value}")]
    OutOfRange {
        /// Name of the offending field.
        field: &'static str,
        /// The accepted range, in words.
        expected: &'static str,
        /// The value received.
        value: f64,
    },
    /// A material string could not be parsed as `category/subtype`.
    #[error(
        "unknown material category {0:?}; expected one of metal, plastic, fabric, leather, foam, rubber, glass, stone, ceramics, wood, concrete, other"
    )]
    UnknownMaterial(String),
    /// A joint referenced a part that is not in the asset.
    #[error("joint {joint:?} references {part}, which is not a part of this asset")]
    UnknownPart {
        /// Joint name.
        joint: String,
        /// The missing part.
        part: PartId,
    },
    /// Two joints share a name, or the joint graph is not a tree.
    #[error("invalid joint structure: {0}")]
    InvalidJointStructure(String),
    /// A value stored by an earlier stage could not be read back.
    #[error("unreadable stored value: {0}")]
    Unreadable(String),
}

/// Result alias for [`TypesError`].
pub type TypesResult<T> = Result<T, TypesError>;
