/// Errors of the decomposition stage.
#[derive(Debug, thiserror::Error)]
pub enum DecomposeError {
    /// The input cannot be decomposed (no faces, not finite, too many faces).
    #[error("cannot decompose: {0}")]
    InvalidInput(String),
    /// An option is out of its domain.
    #[error("invalid decomposition option: {0}")]
    InvalidOption(String),
    /// A geometric computation failed.
    #[error(transparent)]
    Geometry(#[from] uniphys_geometry::GeometryError),
}

/// Result of the decomposition stage.
pub type DecomposeResult<T> = Result<T, DecomposeError>;
