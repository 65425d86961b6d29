use crate::validate::Violation;

/// Everything that can stop the LVLM grounding stage. Each message says what is wrong and what to
/// do about it.
#[derive(Debug, thiserror::Error)]
pub enum AnnotateError {
    /// The input has no parts.
    #[error("the asset has no parts to annotate")]
    NoParts,
    /// More parts than one properties request may carry (reference: 50).
    #[error(
        "the asset has {parts} parts; one LVLM properties request carries at most {max}: merge parts before annotating, or ground it with the built-in grounder"
    )]
    TooManyParts {
        /// Parts in the input.
        parts: usize,
        /// The limit.
        max: usize,
    },
    /// Meshes, colours and names of the input do not line up.
    #[error(
        "annotation input needs one mesh, colour and name per part: {meshes} meshes, {colours} colours, {names} names"
    )]
    InputMismatch {
        /// Meshes given.
        meshes: usize,
        /// Colours given.
        colours: usize,
        /// Names given.
        names: usize,
    },
    /// The model's answer broke the schema, and so did its answer to the repair turn.
    #[error(
        "the LVLM {purpose} answer is invalid after a repair turn ({} violation(s)): {}",
        violations.len(),
        violations.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
    )]
    InvalidAnswer {
        /// Which request (`properties`, `articulation part 3`).
        purpose: String,
        /// Every violation of the last answer.
        violations: Vec<Violation>,
    },
    /// A movable part's articulation could not be settled (its answer stayed invalid after the
    /// repair turn, or named no candidate).
    #[error("the articulation of part {label} failed: {reason}")]
    ArticulationFailed {
        /// Part label (1-based, as in the prompts).
        label: u32,
        /// Why.
        reason: String,
    },
    /// The client gave up (transport, HTTP, budget, timeouts after retries).
    #[error(transparent)]
    Lvlm(#[from] uniphys_lvlm::LvlmError),
    /// A render could not be made or encoded.
    #[error(transparent)]
    Render(#[from] uniphys_render::RenderError),
    /// A render thread stopped without its image.
    #[error("rendering the request images failed: {0}")]
    RenderFailed(String),
    /// An option is outside its domain.
    #[error("invalid annotation option {name}: {reason}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// What is accepted.
        reason: String,
    },
}

/// Result alias for [`AnnotateError`].
pub type AnnotateResult<T> = Result<T, AnnotateError>;
