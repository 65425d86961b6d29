use uniphys_types::PartId;

/// Errors of the built-in grounder.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GroundError {
    /// The asset has no parts.
    #[error("the asset has no parts to ground")]
    NoParts,
    /// A declared joint names a part index that does not exist.
    #[error("declared joint {joint:?} references {part}, which does not exist")]
    JointReferencesMissingPart {
        /// Joint name.
        joint: String,
        /// The missing part.
        part: PartId,
    },
    /// A part is the child of two declared joints.
    #[error("{part} is the child of two joints; an articulation must be a tree")]
    TwoParents {
        /// The part.
        part: PartId,
    },
    /// The declared joints form a cycle, so no part is the root.
    #[error("the declared joints form a cycle: no part is the root")]
    NoRoot,
}

/// Result alias for [`GroundError`].
pub type GroundResult<T> = Result<T, GroundError>;
