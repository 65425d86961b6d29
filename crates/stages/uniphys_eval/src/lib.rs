//! Evaluation of the UniPhys paper (reference section 16).
//!
//! The metrics are pure functions over plain structs: kinematic parameters, articulation
//! structure, part-level intrinsic physics and object-level properties
//! (`kinematics.rs`, `structure.rs`, `physics.rs`, `object.rs`; no IO). Every task returns a
//! [`TaskReport`] of `paper_metrics`, `counts` and `extra_metrics`; a metric is `None` when no
//! valid pair contributed. Accuracies, mIoU, F1 and MnRE are in `[0, 1]`.
//!
//! Around them, `uniphys eval`'s inputs: [`AnnotatedAsset`] is one side of a pair, loaded from
//! our `record.json` (`load_record.rs`), a URDF ingested like a run (`load_mesh_asset.rs`), or a
//! UniPhys-40K entity (`load_dataset.rs`); `pairing.rs` matches joints and parts by name and
//! maps pivots into the `[0, 2]` model frame; where a prediction's part names say nothing of the
//! truth (a decomposed mesh), `part_overlap.rs` first renames its parts to the true parts they
//! share most surface with (surfaces from `load_surfaces.rs`); [`evaluate_pairs`] and
//! [`evaluate_paths`] build the [`EvalReport`] (`eval_report.rs`), printed by
//! [`report_tables`]; [`compare_joints`] lists each true joint next to its prediction
//! (`per_joint.rs`).

mod annotated;
mod common;
mod error;
mod eval_report;
mod kinematic_measures;
mod kinematics;
mod load;
mod load_dataset;
mod load_mesh_asset;
mod load_record;
mod load_surfaces;
mod member_ids;
mod object;
mod pairing;
mod part_overlap;
mod per_joint;
mod physics;
mod report;
mod report_tables;
mod structure;

pub use annotated::{AnnotatedAsset, AnnotatedJoint, AnnotatedPart};
pub use common::{RunningMean, abs_error, alde, mnre};
pub use error::{EvalError, EvalResult};
pub use eval_report::{
    EVAL_SCHEMA_VERSION, EvalInput, EvalReport, InputSummary, PredictionAndTruth, TASKS,
    evaluate_pairs, evaluate_paths, load_pairs, load_pairs_by_overlap,
};
pub use kinematic_measures::{
    axis_angular_error_degrees, canonical_interval, interval_iou, point_to_line_distance,
};
pub use kinematics::{JointPrediction, KinematicSample, evaluate_kinematics};
pub use load::{GroundTruthKind, ground_truth_kind, load_ground_truth, load_prediction};
pub use load_dataset::{is_dataset_entity, load_dataset_ground_truth};
pub use load_mesh_asset::{annotated_from_mesh_asset, load_urdf_asset, load_urdf_ground_truth};
pub use load_record::{RECORD_FILE, annotated_from_record, read_record, record_path};
pub use load_surfaces::{
    load_ground_truth_with_surfaces, load_prediction_with_surfaces, mesh_asset_part_surfaces,
    record_part_surfaces,
};
pub use member_ids::{IdSet, normalise_id, normalise_id_set};
pub use object::{ObjectSample, ObjectValues, evaluate_object, valid_dimensions};
pub use pairing::{PairSamples, pair_samples};
pub use part_overlap::{
    MIN_MATCH_IOU, PartOverlap, PartSurface, match_parts_by_overlap, renamed_by_overlap,
};
pub use per_joint::{JointComparison, compare_joints, joint_kind_word, per_joint_table};
pub use physics::{PhysicalProperties, PhysicsSample, evaluate_physics, material_category};
pub use report::TaskReport;
pub use report_tables::{format_metric, report_tables};
pub use structure::{StructureSample, evaluate_structure, set_iou};
