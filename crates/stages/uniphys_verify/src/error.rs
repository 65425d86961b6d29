use uniphys_types::PartId;

/// Errors of verification.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    /// Part meshes and colliders do not line up with the record's parts.
    #[error(
        "verification needs one mesh and one collider set per part: {parts} parts, {meshes} meshes, {colliders} collider sets"
    )]
    PartCountMismatch {
        /// Parts in the record.
        parts: usize,
        /// Meshes given.
        meshes: usize,
        /// Collider sets given.
        colliders: usize,
    },
    /// A joint names a part that does not exist.
    #[error("joint {joint:?} refers to part {part}, which does not exist")]
    MissingPart {
        /// Joint name.
        joint: String,
        /// The missing part.
        part: PartId,
    },
    /// A parameter is out of its domain.
    #[error("invalid verification parameter: {0}")]
    InvalidParameter(String),
    /// A geometric computation failed.
    #[error(transparent)]
    Geometry(#[from] uniphys_geometry::GeometryError),
}

/// Result of verification functions.
pub type VerifyResult<T> = Result<T, VerifyError>;
