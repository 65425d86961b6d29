use uniphys_types::PartId;

/// Why the dynamic check could not run (an asset that runs and misbehaves is a verdict, not an
/// error).
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// The record breaks its structural invariants (see `AssetRecord::validate`).
    #[error("invalid asset record")]
    InvalidRecord(#[from] uniphys_types::TypesError),
    /// The colliders do not line up with the parts.
    #[error("expected colliders for {parts} parts, got {colliders}")]
    ColliderCount {
        /// Number of parts in the record.
        parts: usize,
        /// Number of collider lists given.
        colliders: usize,
    },
    /// A part's mass properties cannot be simulated (mass not positive or inertia not finite).
    #[error("unusable mass properties for {part}: {reason}")]
    MassProperties {
        /// The part.
        part: PartId,
        /// What is wrong.
        reason: String,
    },
    /// A parameter is out of its valid range.
    #[error("invalid parameter {name}: {reason}")]
    InvalidParams {
        /// Parameter name.
        name: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The physics engine refused a joint (for example a cycle in the articulation).
    #[error("the physics engine rejected joint {joint:?}")]
    JointRejected {
        /// Joint name.
        joint: String,
    },
}

/// Result alias of this crate.
pub type SimulateResult<T> = Result<T, SimulateError>;
