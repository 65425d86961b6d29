//! Stage 2, decomposition: turns a mesh (one piece, or over- or under-segmented parts) into
//! parts that move and are made of one material.
//!
//! The map, in the order the stage runs:
//! - [`views`]: multi-view face-ID renders of the merged mesh (CPU, deterministic);
//! - [`segment`]: a [`Segmenter`] gives a label map per view (built-in render-space segmenter,
//!   or a SAM-compatible service), and overlapping masks become label maps;
//! - [`lift`] and [`consensus`]: labels lifted to faces by pixel majority per view, then merged
//!   across views; [`prior`] estimates the part-count prior K; [`perception`] runs these
//!   ([`perceive`]);
//! - [`candidates`]: a [`CandidateGenerator`] gives decompositions for K in a range (built-in
//!   geometric clustering, or per-face features from a PartField-compatible service);
//!   [`providers`] picks the segmenter and generator from the service settings;
//! - [`select`] with an optimal assignment: the candidate that best matches the lifted masks per view;
//! - [`apriori`], [`refine`] and [`small_parts`]: merge groups mined across views, connectivity
//!   split, small fragments merged; [`handles`]: a panel carrying a handle (a door, a drawer
//!   front) split back out of the merge; all thresholds relative to the object size; [`pieces`]: the
//!   mesh's connected pieces made whole, two big pieces of one part neither inside the other (a
//!   laptop's screen and base) kept as two, small compact pieces (knobs, buttons) kept as parts,
//!   also when drawn into a panel's surface, and caps drawn onto a neck ([`pockets`]: smooth
//!   regions behind one crease);
//!   [`round`]: whether a part maps onto itself when turned (a wheel or a dial is kept, since
//!   it can spin against what it is attached to); [`hidden`]: parts hidden inside the closed
//!   object (unreachable, so not operable) merged into the largest part; [`layers`]: thin
//!   sheets stacked flat against each other (a door's skin and liner) joined into one panel;
//!   [`tops`]: a board topping the object with no cavity under it (a table's top, a cooktop)
//!   joined to the largest part;
//! - [`mod@decompose`]: the whole stage, and [`output`]: per-part meshes and the face-to-part map;
//!   [`score`]: part-count error and area-weighted IoU against known parts (tests, benchmark);
//! - [`policy`]: which inputs are decomposed ([`DecomposeMode`]); [`split`]: a stored
//!   face-to-part map applied to its asset.

pub mod apriori;
pub mod candidates;
pub mod consensus;
pub mod decompose;
mod error;
pub mod handles;
pub mod hidden;
pub mod layers;
pub mod lift;
pub mod output;
mod part_faces;
pub mod perception;
pub mod pieces;
pub mod pockets;
pub mod policy;
pub mod prior;
pub mod providers;
pub mod refine;
pub mod round;
pub mod score;
pub mod segment;
pub mod select;
mod sheet_shape;
pub mod small_parts;
pub mod split;
pub mod tops;
pub mod views;

pub use candidates::{
    Candidate, CandidateGenerator, CandidateRequest, GeometricGenerator, cluster_faces,
};
pub use decompose::{DecomposeOptions, decompose, decompose_asset};
pub use error::{DecomposeError, DecomposeResult};
pub use hidden::{HiddenOptions, merge_hidden_parts};
pub use layers::{LayerOptions, merge_layers};
pub use lift::FaceSet;
pub use output::{DecomposeSummary, Decomposition, StepLabels};
pub use perception::{Perception, PerceptionOptions, perceive};
pub use pieces::{PieceOptions, PieceReport, mesh_pieces, respect_pieces};
pub use policy::{DecomposeMode, FRAGMENTED_PART_COUNT, needs_decomposition};
pub use prior::k_range;
pub use providers::{generator_for, segmenter_for};
pub use score::{PartMatching, PartScore, match_parts, score_parts};
pub use segment::{BuiltinSegmenter, LabelMap, Segmenter, ViewImage};
pub use split::split_asset;
pub use tops::{TopOptions, merge_tops};
pub use views::{ViewOptions, ViewSet, face_colours, render_views};
