//! Matching a prediction to its ground truth and building the metric samples.
//!
//! Matching is by part name: a GT movable joint (`B` or `C`) is paired with the predicted joint
//! whose child part has the same name. No predicted joint for that child is a missing prediction
//! and a fixed (`D`) one is a wrong type; both count against joint type accuracy (reference
//! 16.1). Predicted joints whose child has no GT movable joint are not scored (they are counted
//! as `extra_pred_movable_joints`). Part physics pairs parts by name; object values pair the
//! two objects.
//!
//! Frames: each side's pivot is mapped into the `[0, 2]` model frame of its own object AABB
//! (reference 14.3). When both sides are the same geometry in the same frame (the usual case:
//! GT loaded with the run's ingest options and rested on the ground like the run) the two frames
//! are identical; when they differ by a translation or a unit (a dataset's raw mesh frame
//! against our rested, metric frame) the difference cancels. Prismatic ranges are divided by
//! their own side's frame scale (the predicted range is expressed in GT units before
//! [`crate::evaluate_kinematics`] divides both by the GT scale).

use serde_json::Value;
use uniphys_geometry::DVec3;

use crate::annotated::AnnotatedAsset;
use crate::{JointPrediction, KinematicSample, ObjectSample, PhysicsSample, StructureSample};

/// The metric samples of one prediction / ground-truth pair, plus matching counts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PairSamples {
    /// One per GT movable joint.
    pub kinematics: Vec<KinematicSample>,
    /// One per GT movable joint.
    pub structure: Vec<StructureSample>,
    /// One per GT part with physical properties.
    pub physics: Vec<PhysicsSample>,
    /// One if the GT has object values.
    pub object: Vec<ObjectSample>,
    /// GT movable joints whose child has a predicted movable joint.
    pub matched_joints: u64,
    /// Predicted movable joints whose child has no GT movable joint.
    pub extra_pred_movable_joints: u64,
    /// GT parts with properties that have a predicted part of the same name.
    pub matched_parts: u64,
}

/// Builds the samples of one pair (see the module documentation for the matching rules).
#[must_use]
pub fn pair_samples(pred: &AnnotatedAsset, gt: &AnnotatedAsset) -> PairSamples {
    let pred_frame = pred.model_frame();
    let gt_frame = gt.model_frame();
    let mut out = PairSamples::default();
    for g in gt.joints.iter().filter(|j| j.is_movable()) {
        let p = pred.joint_of(&g.child);
        let unit_ratio = match (pred_frame, gt_frame) {
            (Some(pf), Some(gf)) => Some(gf.scale_m / pf.scale_m),
            _ => None,
        };
        let prediction = p.map(|p| JointPrediction {
            motion_type: Some(p.motion_type),
            axis: p.is_movable().then_some(p.axis),
            pivot_model: pred_frame
                .zip(p.pivot_in_object)
                .map(|(f, pivot)| f.point_source_to_model(DVec3::from_array(pivot)).to_array()),
            range: match (p.range, p.motion_type) {
                (Some(r), 'C') => Some(r),
                (Some(r), 'B') => unit_ratio.map(|k| [r[0] * k, r[1] * k]),
                _ => None,
            },
        });
        out.kinematics.push(KinematicSample {
            gt_type: Some(g.motion_type),
            pred: prediction,
            gt_axis: Some(g.axis),
            gt_pivot_model: gt_frame
                .zip(g.pivot_in_object)
                .map(|(f, pivot)| f.point_source_to_model(DVec3::from_array(pivot)).to_array()),
            gt_range: g.range,
            frame_scale: gt_frame.map(|f| f.scale_m),
        });
        let movable = p.filter(|p| p.is_movable());
        out.matched_joints += u64::from(movable.is_some());
        out.structure.push(StructureSample {
            pred: movable.map(|p| names(&p.members)),
            gt: Some(names(&g.members)),
        });
    }
    out.extra_pred_movable_joints = pred
        .joints
        .iter()
        .filter(|p| p.is_movable())
        .filter(|p| gt.joint_of(&p.child).is_none_or(|g| !g.is_movable()))
        .count() as u64;
    for g in &gt.parts {
        let Some(gt_physics) = &g.physics else {
            continue;
        };
        let p = pred.part(&g.name);
        out.matched_parts += u64::from(p.is_some());
        out.physics.push(PhysicsSample {
            pred: p.and_then(|p| p.physics.clone()),
            gt: gt_physics.clone(),
        });
    }
    if let Some(gt_object) = &gt.object {
        out.object.push(ObjectSample {
            pred: pred.object.clone(),
            gt: gt_object.clone(),
        });
    }
    out
}

fn names(members: &[String]) -> Value {
    Value::Array(members.iter().cloned().map(Value::String).collect())
}
