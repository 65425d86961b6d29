/// Errors of the decomposition stage.
#[derive(Debug, thiserror::Error)]
pub enum DecomposeError {
    /// The input cannot be decomposed (no faces, not finite, too many faces).
    #[error("cannot decompose: {0}")]
    InvalidInput(String),
    /// An option is out of its domain.
    #[error("invalid decomposition option: {0}")]
    InvalidOption(String),
    /// No face is visible in any rendered view.
    #[error("no face is visible in any view")]
    NothingVisible,
    /// The segmentation of every view lifted to no face.
    #[error("the view segmentations lifted to no face (no mask in any view)")]
    NoMasks,
    /// A segmenter failed on a view or returned an unusable label map.
    #[error("segmenting view {view}: {message}")]
    Segmentation {
        /// Index of the view.
        view: usize,
        /// What went wrong.
        message: String,
    },
    /// Writing the stage's outputs failed.
    #[error("writing the decomposition: {0}")]
    Output(String),
    /// A geometric computation failed.
    #[error(transparent)]
    Geometry(#[from] uniphys_geometry::GeometryError),
    /// A remote vision service (SAM-compatible masks, PartField-compatible features) failed.
    #[error(transparent)]
    Vision(#[from] uniphys_vision::VisionError),
}

impl DecomposeError {
    /// Whether the same run may succeed later: a vision service that stayed away through its
    /// retries may be back; every other failure would repeat.
    #[must_use]
    pub fn is_transient(&self) -> bool {
        matches!(
            self,
            Self::Vision(uniphys_vision::VisionError::GaveUp { .. })
        )
    }
}

/// Result of the decomposition stage.
pub type DecomposeResult<T> = Result<T, DecomposeError>;
