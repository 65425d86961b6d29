//! The learned grounding path: a UniPhysGen model server predicts part physics, part motion and
//! object-level properties (`infer_answers`: the `infer` stage, whose [`ModelAnswers`] the queue
//! stores); its answers replace the built-in grounder's values in the record (`apply_answers`, in
//! the `ground` stage), so verification and export work unchanged and every value names the
//! model.
//!
//! The articulation tree (which part hangs from which) still comes from the input or the
//! geometric heuristic: the model predicts how a part moves, not what it is attached to.

use uniphys_geometry::{DMat3, DVec3, MeshAsset, TriMesh};
use uniphys_ground::{PartInput, RigidMass, articulate};
use uniphys_types::{AssetRecord, Joint, JointKind};
use uniphys_uniphysgen::restore::{restore_motion, restore_object, restore_physics};
use uniphys_uniphysgen::{
    ClientConfig, MODEL_ANSWERS_VERSION, ModelAnswers, PointOptions, Task, UniPhysGenClient,
    model_inputs, prepare_points,
};

use crate::PipelineResult;
use crate::grounding::Prepared;

/// How to reach the model server and prepare its inputs.
#[derive(Debug, Clone)]
pub struct LearnedOptions {
    /// Server address, timeouts, retries, batching.
    pub client: ClientConfig,
    /// GPU slots this process may hold at once.
    pub slots: usize,
    /// Point-cloud sizes and seed.
    pub points: PointOptions,
    /// Voxel grid bins over the [0, 2] frame.
    pub num_bins: u32,
}

impl Default for LearnedOptions {
    fn default() -> Self {
        Self {
            client: ClientConfig::default(),
            slots: 1,
            points: PointOptions::default(),
            num_bins: uniphys_uniphysgen::DEFAULT_NUM_BINS,
        }
    }
}

/// Asks the model server about `asset`'s parts and its object (`sample` names it): its answers,
/// with the frame they are in.
pub(crate) fn infer_answers(
    asset: &MeshAsset,
    sample: &str,
    options: &LearnedOptions,
) -> PipelineResult<ModelAnswers> {
    let points = prepare_points(asset, &options.points)?;
    let inputs = model_inputs(&points, options.num_bins)?;
    let client = UniPhysGenClient::new(options.client.clone(), options.slots)?;
    let physics = client.predict_parts(Task::Physics, sample, &inputs)?;
    let motion = client.predict_parts(Task::Kinematics, sample, &inputs)?;
    let (object_model, object) = client.predict_object(sample, &inputs)?;
    Ok(ModelAnswers {
        version: MODEL_ANSWERS_VERSION,
        base_url: options.client.base_url.clone(),
        frame: inputs.frame.to_json(),
        part_centers_in_object_m: points
            .part_centers_in_object_m
            .iter()
            .map(|c| c.to_array())
            .collect(),
        physics,
        motion,
        object_model,
        object,
    })
}

/// Replaces properties, joints and object name/category/mass in `record` with the model's
/// `answers`. Returns notes for the report.
pub(crate) fn apply_answers(
    asset: &MeshAsset,
    prepared: &[Prepared],
    colliders: &[Vec<TriMesh>],
    record: &mut AssetRecord,
    answers: &ModelAnswers,
) -> PipelineResult<Vec<String>> {
    let mut notes = Vec::new();
    let physics = &answers.physics;
    for (part, answer) in record.parts.iter_mut().zip(&physics.parts) {
        let Some(values) = &answer.physical_properties else {
            notes.push(format!(
                "{}: the model gave no physics; built-in values kept",
                part.id
            ));
            continue;
        };
        part.replace_properties(restore_physics(&answer.id, values, &physics.model)?);
    }

    let motion = &answers.motion;
    let frame = answers.coordinate_frame();
    let mut declared = Vec::with_capacity(record.joints.len());
    for joint in &record.joints {
        let i = joint.child.0 as usize;
        let (Some(answer), Some(center)) =
            (motion.parts.get(i), answers.part_centers_in_object_m.get(i))
        else {
            continue;
        };
        let restored = restore_motion(answer, &frame, DVec3::from_array(*center), &motion.model)?;
        declared.push(match restored {
            Some(m) => Joint {
                name: String::new(),
                kind: m.kind,
                axis_in_object: m.axis_in_object,
                pivot_in_object_m: m.pivot_in_object_m,
                limits: m.limits,
                damping: 0.0,
                friction: 0.0,
                coupled_parts: Vec::new(),
                provenance: m.provenance,
                ..joint.clone()
            },
            None => Joint {
                kind: JointKind::Fixed,
                name: String::new(),
                damping: 0.0,
                friction: 0.0,
                ..joint.clone()
            },
        });
    }
    if motion
        .parts
        .get(record.root.0 as usize)
        .is_some_and(|a| a.motion_type.is_some())
    {
        notes.push(format!(
            "the model says the root {} moves; it stays fixed to the world",
            record.root
        ));
    }
    let masses: Vec<RigidMass> = record
        .parts
        .iter()
        .map(|p| RigidMass {
            mass_kg: p.mass.mass_kg.value,
            com: DVec3::from_array(p.mass.com_in_object_m),
            inertia_about_com_kg_m2: DMat3::from_cols_array_2d(&p.mass.inertia_about_com_kg_m2)
                .transpose(),
        })
        .collect();
    let parts: Vec<PartInput<'_>> = asset
        .parts
        .iter()
        .zip(prepared)
        .zip(&masses)
        .zip(colliders)
        .map(|(((p, prep), mass), hulls)| PartInput {
            name: &p.name,
            mesh: &p.mesh,
            volume_m3: prep.mass.volume_m3,
            mass: *mass,
            colliders: hulls,
        })
        .collect();
    let articulation = articulate(&parts, &declared)?;
    record.joints = articulation.joints;
    notes.extend(articulation.notes);

    let model = &answers.object_model;
    let object = restore_object(&answers.object, model)?;
    record.object.name = object.name;
    record.object.category = object.category;
    record.object.mass_kg = object.mass_kg;
    record.validate()?;
    notes.push(format!(
        "grounded by the UniPhysGen model {model:?} at {}",
        answers.base_url
    ));
    Ok(notes)
}
