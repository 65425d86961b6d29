//! LVLM grounding (stages 3 and 4 of the product): a vision-language model annotates an asset's
//! object and part properties from rendered views, the motion graph is built from its answer, and
//! each movable part's joint is chosen by the model among geometric candidates.
//!
//! Map of the crate:
//! - [`prompt`]: the versioned prompt files and how they are filled;
//! - [`schema`]: the answers as serde types; [`validate`]: every schema violation with its path;
//! - [`quantities`]: unit strings of the answers → SI; [`convert`]: answers → domain types;
//! - `colours`: legend colour names → candidate index;
//! - [`motion_graph`]: movable parts, parents, co-moving groups and the issues of the answer;
//! - [`articulation`]: candidates of a movable part and the model's choice among them;
//! - `views`: the request images (part composites, candidate axes, candidate pivots);
//! - `ask`: one request with validation and one repair turn;
//! - `part_request`: one movable part's articulation request;
//! - `stage`: [`annotate`], the whole stage;
//! - `error`: [`AnnotateError`].

pub mod articulation;
mod ask;
mod colours;
pub mod convert;
mod error;
pub mod motion_graph;
mod part_request;
pub mod prompt;
pub mod quantities;
pub mod schema;
mod stage;
pub mod validate;
mod views;

pub use ask::{Asked, ask_validated};
pub use colours::{colour_index, normalise_colour};
pub use error::{AnnotateError, AnnotateResult};
pub use motion_graph::{
    FixedLink, MotionGraph, MotionIssue, MotionIssueKind, MovablePart, motion_graph,
};
pub use prompt::PROMPT_VERSION;
pub use stage::{
    AnnotateInput, AnnotateOptions, AnnotateTimings, Annotation, ArticulationFailure, MAX_PARTS,
    Repair, annotate,
};
pub use validate::{Violation, validate_articulation, validate_properties};
pub use views::{AXIS_LEGEND, PIVOT_LEGEND};
