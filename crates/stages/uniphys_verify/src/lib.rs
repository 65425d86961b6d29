//! Verification of grounded assets (stage 6 of the product):
//!
//! - intrinsic checks per part and object, levels 0-4 of the reference ([`verify_intrinsic`]);
//! - articulation sweeps: each joint moved through its range; contact with its parent, the
//!   moving surface passing through the other parts' own triangles (`crossing`), a short
//!   slide's gap to its parent, its direction against the face it sits on and which way it
//!   goes (into a face around it, off a parent it caps: [`SlideSide`]), no slide of a part its
//!   parent holds from both ends along the axis ([`SlideTrap`]), a long slide in a slot
//!   it stays in or lifted across a sheet's own plane, and no hinge about a slot's axis
//!   (`slot`), a turning axis held by its part, a panel's hinge away from its handle and along
//!   a bar handle ([`panel_handle`]), a sheet held along an edge hinged where it meets its
//!   parent, a panel turned in its own plane only when round or held
//!   across both faces ([`InPlaneTurn`]), a part spun without limit about the line it is round
//!   about when it is round about one ([`OffRoundSpin`]), nothing taken below the ground the
//!   object stands on (when it rests on one: `ground`), and interpenetration of convex
//!   colliders (a measure for grounders) ([`sweep`], [`Scene`]); the verdict on a sweep, which
//!   rules it breaks and how badly (`verdict`: [`SweepMetrics::failures`],
//!   [`SweepMetrics::severity`]);
//! - one joint judged and, if it fails, corrected in tiers of growing change ([`verify_joint`],
//!   [`correct_joint`]; the tiers' variants built in `variants`) from the articulation candidates
//!   of the contact geometry, the part's edge lines, the cross-sections of its edges, the centres
//!   of its rounded ends and of the region its parent holds on both faces
//!   ([`articulation_candidates`], [`edge_pivots`], [`band_pivots`], [`rounded_end_pivots`],
//!   [`held_pivots`]), also used by grounders to enumerate hypotheses, and the line a spinning part
//!   is round about; corrections compared by how well they fit the part (`fit`); a round part's
//!   shape about a line and whether a hand would press it or turn it ([`RoundAxis`]), which the
//!   grounder asks too;
//! - the whole articulation at once ([`verify_articulation`]).
//!
//! Distance thresholds are fractions of the object's diagonal or of the parts involved, so
//! results do not depend on the object's scale or pose.

mod articulation;
mod candidates;
mod contact_reference;
mod correct;
mod crossing;
mod error;
mod fit;
mod ground;
mod handle;
mod held;
mod in_plane;
mod intrinsic;
mod motion;
mod off_round;
mod part_box;
mod patch;
mod penetration;
mod plausibility;
mod round_axis;
mod rounded_ends;
mod scene;
mod slide_side;
mod slide_trap;
mod slot;
mod sweep;
mod sweep_params;
mod variants;
mod verdict;

pub use articulation::{ArticulationOutcome, JointVerdict, verify_articulation, verify_joint};
pub use candidates::{
    AXIS_CANDIDATES, ArticulationCandidates, PIVOT_CANDIDATES, articulation_candidates,
    band_pivots, edge_pivots,
};
pub use correct::{Correction, correct_joint};
pub use error::{VerifyError, VerifyResult};
pub use ground::{FOOTPRINT_SHARE_MIN, GROUND_TOUCH_FRACTION, stands_on_ground};
pub use handle::{PANEL_SLAB_RATIO, panel_handle};
pub use in_plane::{InPlaneTurn, held_pivots};
pub use intrinsic::{IntrinsicOutcome, MASS_RELATIVE_ERROR_MAX, part_checks, verify_intrinsic};
pub use motion::{JointMotion, sweep_coordinates};
pub use off_round::OffRoundSpin;
pub use part_box::PartBox;
pub use patch::{PatchParams, grow_patch};
pub use plausibility::plausibility_checks;
pub use round_axis::{
    ON_SURFACE_FRACTION, RoundAxis, SMALL_PART_FRACTION, across, centre_about, kept_about_line,
    push_travel_m,
};
pub use rounded_ends::rounded_end_pivots;
pub use scene::{Scene, moving_group};
pub use slide_side::SlideSide;
pub use slide_trap::SlideTrap;
pub use sweep::{SweepMetrics, sweep};
pub use sweep_params::SweepParams;
