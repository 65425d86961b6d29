/// Errors of the in-process pipeline, one variant per stage that can fail.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The input could not be read.
    #[error(transparent)]
    Ingest(#[from] uniphys_mesh_io::IngestError),
    /// A geometric computation failed.
    #[error("geometry of part {part:?}: {source}")]
    Geometry {
        /// Part name.
        part: String,
        /// The error.
        #[source]
        source: uniphys_geometry::GeometryError,
    },
    /// Grounding failed.
    #[error(transparent)]
    Ground(#[from] uniphys_ground::GroundError),
    /// Verification could not run (not: the asset failed a check; that is in the report).
    #[error(transparent)]
    Verify(#[from] uniphys_verify::VerifyError),
    /// The dynamic check could not run (not: the asset failed it; that is in the report).
    #[error(transparent)]
    Simulate(#[from] uniphys_simulate::SimulateError),
    /// Export failed.
    #[error(transparent)]
    Export(#[from] uniphys_export::ExportError),
    /// The assembled record broke an invariant (a bug in an earlier stage).
    #[error("assembled asset record is invalid: {0}")]
    Record(#[from] uniphys_types::TypesError),
    /// The UniPhysGen model server could not be used or gave an unusable answer.
    #[error(transparent)]
    Model(#[from] uniphys_uniphysgen::UniPhysGenError),
    /// The LVLM grounding stage failed (answers invalid after repair, too many parts).
    #[error(transparent)]
    Annotate(#[from] uniphys_annotate::AnnotateError),
    /// The LVLM client could not be set up (configuration, cache directory).
    #[error(transparent)]
    Lvlm(#[from] uniphys_lvlm::LvlmError),
    /// The preview could not be rendered or encoded.
    #[error("preview render: {0}")]
    Render(#[from] uniphys_render::RenderError),
    /// Decomposition into parts failed.
    #[error(transparent)]
    Decompose(#[from] uniphys_decompose::DecomposeError),
    /// The input has nothing to process.
    #[error("{0}")]
    Empty(String),
    /// A grounding stored by an earlier `ground` stage does not fit the input it is applied to.
    #[error("the stored grounding does not fit the input: {0}")]
    StoredGrounding(String),
    /// A verification stored by an earlier `verify` stage does not fit the grounding it is
    /// applied to.
    #[error("the stored verification does not fit the grounding: {0}")]
    StoredVerification(String),
}

impl PipelineError {
    /// Whether the same run may succeed later: a model server (LVLM, UniPhysGen) or vision
    /// service that stayed away, or answered out of format, through every retry (answers
    /// already paid for are cached). Every other failure would repeat.
    #[must_use]
    pub fn is_transient(&self) -> bool {
        use uniphys_uniphysgen::UniPhysGenError;
        match self {
            Self::Lvlm(e) | Self::Annotate(uniphys_annotate::AnnotateError::Lvlm(e)) => {
                e.is_transient()
            }
            Self::Model(e) => matches!(
                e,
                UniPhysGenError::GaveUp { .. }
                    | UniPhysGenError::Timeout { .. }
                    | UniPhysGenError::NoSlot { .. }
            ),
            Self::Decompose(e) => e.is_transient(),
            _ => false,
        }
    }
}

/// Result alias for [`PipelineError`].
pub type PipelineResult<T> = Result<T, PipelineError>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn servers_that_stayed_away_are_transient_and_bad_inputs_are_not() {
        let lvlm_away = uniphys_lvlm::LvlmError::GaveUp {
            purpose: "properties".into(),
            attempts: 4,
            last_failure: "HTTP 503".into(),
        };
        assert!(PipelineError::Lvlm(lvlm_away).is_transient());
        let vision_away = uniphys_vision::VisionError::GaveUp {
            service: "sam",
            path: "/v1/masks",
            base_url: "http://sam".into(),
            attempts: 4,
            reason: "timeout".into(),
        };
        let decompose = uniphys_decompose::DecomposeError::Vision(vision_away);
        assert!(decompose.is_transient());
        assert!(PipelineError::Decompose(decompose).is_transient());
        assert!(!PipelineError::Empty("no parts".into()).is_transient());
        assert!(
            !PipelineError::Annotate(uniphys_annotate::AnnotateError::ArticulationFailed {
                label: 2,
                reason: "invalid".into(),
            })
            .is_transient()
        );
    }
}
