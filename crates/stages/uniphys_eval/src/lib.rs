//! Evaluation metrics of the UniPhys paper (reference section 16) as pure functions over plain
//! structs: kinematic parameters, articulation structure, part-level intrinsic physics and
//! object-level properties. No IO: callers load records and build the sample structs.
//!
//! Every task returns a [`TaskReport`] of `paper_metrics`, `counts` and `extra_metrics`; a metric
//! is `None` when no valid pair contributed. Accuracies, mIoU, F1 and MnRE are in `[0, 1]`.

mod common;
mod error;
mod kinematic_measures;
mod kinematics;
mod member_ids;
mod object;
mod physics;
mod report;
mod structure;

pub use common::{RunningMean, abs_error, alde, mnre};
pub use error::EvalError;
pub use kinematic_measures::{
    axis_angular_error_degrees, canonical_interval, interval_iou, point_to_line_distance,
};
pub use kinematics::{JointPrediction, KinematicSample, evaluate_kinematics};
pub use member_ids::{IdSet, normalise_id, normalise_id_set};
pub use object::{ObjectSample, ObjectValues, evaluate_object, valid_dimensions};
pub use physics::{PhysicalProperties, PhysicsSample, evaluate_physics, material_category};
pub use report::TaskReport;
pub use structure::{StructureSample, evaluate_structure, set_iou};
