//! The rapier world of an asset: one multibody rooted at the fixed root part, one rigid body per
//! part (its frame is the object frame at rest, so colliders and mass properties go in
//! unchanged), and per-DoF damping, dry friction and armature as the MJCF export writes them.
//!
//! Why a multibody (reduced coordinates) and not impulse joints: the joint coordinate `q` is a
//! state of the solver, so drift is measured without reconstructing it from two poses; joints
//! cannot open up (no constraint drift that would look like motion); and rapier's multibody has
//! MuJoCo's joint model, with implicit damping, `frictionloss` and armature per DoF, which
//! impulse joints do not.

use rapier3d::prelude::{
    ActiveHooks, ColliderBuilder, GenericJoint, IntegrationParameters, JointAxesMask, JointAxis,
    MassProperties, Matrix, MotorModel, MultibodyJointHandle, PhysicsWorld, PrismaticJointBuilder,
    Real, RevoluteJointBuilder, RigidBodyBuilder, RigidBodyHandle, Vector,
};
use uniphys_geometry::{DVec3, TriMesh};
use uniphys_types::{AssetRecord, JointKind, PartId};

use crate::engine_guard::guarded;
use crate::filter::PairFilter;
use crate::{DynamicParams, SimulateError, SimulateResult};

/// A joint of the asset inside the engine.
#[derive(Debug, Clone, Copy)]
struct EngineJoint {
    handle: MultibodyJointHandle,
    axis: JointAxis,
    /// Index of the coordinate in `MultibodyJoint::coords`.
    coord: usize,
}

/// A running simulation of one asset.
pub(crate) struct Scene {
    world: PhysicsWorld,
    filter: PairFilter,
    /// Body of each part, by position in `record.parts`.
    bodies: Vec<RigidBodyHandle>,
    /// Engine joint of each record joint (`None` for fixed joints).
    joints: Vec<Option<EngineJoint>>,
    /// Largest distance from a body's centre of mass to its colliders, m.
    body_radius_m: Vec<f64>,
    gravity_m_per_s2: f64,
    /// Hulls that could not be turned into colliders (degenerate), as notes.
    pub notes: Vec<String>,
}

/// Kinematic summary of all bodies at one instant.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BodyState {
    /// Largest speed of any collider point of any body, m/s (`|v| + |w| r`).
    pub max_point_speed_m_per_s: f64,
    /// Kinetic plus gravitational potential energy of all moving bodies, J.
    pub energy_j: f64,
    /// Whether every pose and velocity is finite.
    pub finite: bool,
}

/// Colliders closer than this share of the object's diagonal get speculative contacts (rapier's
/// `normalized_prediction_distance`; the engine's length unit is the diagonal). Rapier's default,
/// 0.02, reaches 4 cm on a 2 m object: each control in a row of buttons or knobs then keeps
/// speculative contacts with its neighbours' hulls: hundreds of multibody contact constraints
/// solved every step, most of a drive's time on a camera with nine controls. 0.005 is 1 cm on a
/// 2 m object, two to three steps of a 1 m door driven at 1 rad/s at 240 Hz.
const PREDICTION_DISTANCE_FRACTION: Real = 0.005;

impl Scene {
    /// Builds the world for `record` (validated by the caller) with `colliders[i]` belonging to
    /// `record.parts[i]`, in the object frame at rest.
    pub fn build(
        record: &AssetRecord,
        colliders: &[Vec<TriMesh>],
        excluded_pairs: &[(PartId, PartId)],
        params: &DynamicParams,
        object_diagonal_m: f64,
    ) -> SimulateResult<Self> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        world.integration_parameters = IntegrationParameters {
            dt: params.dt_s() as Real,
            length_unit: object_diagonal_m.clamp(0.01, 10.0) as Real,
            // No speed cap: an explosion must show, not be clipped at 400 m/s.
            normalized_max_linear_velocity: Real::MAX,
            num_solver_iterations: params.solver_iterations,
            normalized_prediction_distance: PREDICTION_DISTANCE_FRACTION,
            ..IntegrationParameters::default()
        };
        let mut notes = Vec::new();
        let mut bodies = Vec::with_capacity(record.parts.len());
        let mut body_radius_m = Vec::with_capacity(record.parts.len());
        for (i, part) in record.parts.iter().enumerate() {
            let builder = if part.id == record.root {
                RigidBodyBuilder::fixed()
            } else {
                RigidBodyBuilder::dynamic()
                    .additional_mass_properties(mass_properties(part)?)
                    .can_sleep(false)
            };
            let body = world.insert_body(builder);
            let com = DVec3::from_array(part.mass.com_in_object_m);
            let mut radius: f64 = 0.0;
            for (k, hull) in colliders[i].iter().enumerate() {
                radius = hull
                    .positions
                    .iter()
                    .map(|p| p.distance(com))
                    .fold(radius, f64::max);
                let points: Vec<Vector> = hull.positions.iter().map(|p| p.as_vec3()).collect();
                let Some(collider) = ColliderBuilder::convex_hull(&points) else {
                    notes.push(format!(
                        "{} hull {k} is degenerate and was left out",
                        part.id
                    ));
                    continue;
                };
                world.insert_collider(
                    collider
                        .density(0.0)
                        .friction(part.properties.friction_coefficient.value as Real)
                        .user_data(i as u128)
                        .active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS),
                    Some(body),
                );
            }
            bodies.push(body);
            body_radius_m.push(radius);
        }
        let mut joints = Vec::with_capacity(record.joints.len());
        // Insert joints parent-first: the engine only attaches a child that is not yet linked.
        let mut order: Vec<usize> = Vec::with_capacity(record.joints.len());
        let mut placed = vec![record.root];
        while order.len() < record.joints.len() {
            let before = order.len();
            for (j, joint) in record.joints.iter().enumerate() {
                if !order.contains(&j) && placed.contains(&joint.parent) {
                    order.push(j);
                    placed.push(joint.child);
                }
            }
            if order.len() == before {
                break;
            }
        }
        joints.resize(record.joints.len(), None);
        let position = |id: PartId| record.parts.iter().position(|p| p.id == id);
        for j in order {
            let joint = &record.joints[j];
            let (Some(parent), Some(child)) = (position(joint.parent), position(joint.child))
            else {
                return Err(SimulateError::JointRejected {
                    joint: joint.name.clone(),
                });
            };
            let axis = DVec3::from_array(joint.axis_in_object).as_vec3();
            let pivot = DVec3::from_array(joint.pivot_in_object_m).as_vec3();
            let limits = joint.limits.map(|l| [l.lower as Real, l.upper as Real]);
            let (data, engine_axis, coord): (GenericJoint, JointAxis, usize) = match joint.kind {
                JointKind::Revolute | JointKind::Continuous => {
                    let mut b = RevoluteJointBuilder::new(axis)
                        .local_anchor1(pivot)
                        .local_anchor2(pivot)
                        .contacts_enabled(false);
                    if let (JointKind::Revolute, Some(l)) = (joint.kind, limits) {
                        b = b.limits(l);
                    }
                    (b.build().into(), JointAxis::AngX, 3)
                }
                JointKind::Prismatic => {
                    let mut b = PrismaticJointBuilder::new(axis)
                        .local_anchor1(pivot)
                        .local_anchor2(pivot)
                        .contacts_enabled(false);
                    if let Some(l) = limits {
                        b = b.limits(l);
                    }
                    (b.build().into(), JointAxis::LinX, 0)
                }
                JointKind::Fixed => (
                    rapier3d::prelude::FixedJointBuilder::new()
                        .contacts_enabled(false)
                        .build()
                        .into(),
                    JointAxis::LinX,
                    usize::MAX,
                ),
            };
            let handle = world
                .insert_multibody_joint(bodies[parent], bodies[child], data)
                .ok_or_else(|| SimulateError::JointRejected {
                    joint: joint.name.clone(),
                })?;
            if joint.kind.is_movable() {
                joints[j] = Some(EngineJoint {
                    handle,
                    axis: engine_axis,
                    coord,
                });
            }
        }
        let mut scene = Self {
            world,
            filter: PairFilter::new(record, excluded_pairs),
            bodies,
            joints,
            body_radius_m,
            gravity_m_per_s2: params.gravity_m_per_s2,
            notes,
        };
        // The fixed root starts as a free 6-DoF root and collapses to 0 DoFs on the first step,
        // which re-indexes the per-DoF vectors: take that step without gravity and with no time
        // passing (nothing moves, not even a joint outside its limits), then set them.
        scene.world.integration_parameters.dt = 0.0;
        scene.world.step_with_events(&scene.filter, &());
        scene.world.integration_parameters.dt = params.dt_s() as Real;
        for (j, joint) in record.joints.iter().enumerate() {
            let Some(engine) = scene.joints[j] else {
                continue;
            };
            let Some((multibody, link_id)) = scene.world.multibody_joints.get_mut(engine.handle)
            else {
                continue;
            };
            let Some(dof) = multibody.link(link_id).map(|l| l.assembly_id()) else {
                continue;
            };
            multibody.damping_mut()[dof] = joint.damping as Real;
            multibody.frictions_mut()[dof] = joint.friction as Real;
            multibody.armature_mut()[dof] = (params.armature_s * joint.damping) as Real;
        }
        scene.world.gravity = Vector::new(0.0, 0.0, -params.gravity_m_per_s2 as Real);
        Ok(scene)
    }

    /// Advances one step; `false` when the engine failed inside it (see `engine_guard`), after
    /// which the scene's state means nothing and it must not be stepped again.
    #[must_use]
    pub fn step(&mut self) -> bool {
        let (world, filter) = (&mut self.world, &self.filter);
        guarded(|| world.step_with_events(filter, &())).is_some()
    }

    /// Coordinate and velocity of record joint `j` (rad, rad/s or m, m/s); `None` for a fixed
    /// joint.
    pub fn joint_state(&self, j: usize) -> Option<(f64, f64)> {
        let engine = self.joints.get(j).copied().flatten()?;
        let (multibody, link_id) = self.world.multibody_joints.get(engine.handle)?;
        let link = multibody.link(link_id)?;
        let q = link.joint().coords()[engine.coord];
        let qd = multibody
            .joint_velocity(link)
            .get(0)
            .copied()
            .unwrap_or(Real::NAN);
        Some((f64::from(q), f64::from(qd)))
    }

    /// Drives record joint `j` at `velocity` (rad/s or m/s) with at most `max_effort` (N m or N),
    /// correcting velocity errors at `gain_per_s`; `None` releases the drive.
    pub fn set_drive(&mut self, j: usize, drive: Option<(f64, f64)>, gain_per_s: f64) {
        let Some(engine) = self.joints.get(j).copied().flatten() else {
            return;
        };
        let Some((multibody, link_id)) = self.world.multibody_joints.get_mut(engine.handle) else {
            return;
        };
        let Some(link) = multibody.link_mut(link_id) else {
            return;
        };
        let data = &mut link.joint.data;
        match drive {
            Some((velocity, max_effort)) => {
                data.set_motor_model(engine.axis, MotorModel::AccelerationBased);
                data.set_motor_velocity(engine.axis, velocity as Real, gain_per_s as Real);
                data.set_motor_max_force(engine.axis, max_effort as Real);
            }
            None => data.motor_axes.remove(JointAxesMask::from(engine.axis)),
        }
    }

    /// Speeds, energy and finiteness of all bodies now.
    pub fn body_state(&self) -> BodyState {
        let gravity = self.gravity_m_per_s2;
        let mut state = BodyState {
            max_point_speed_m_per_s: 0.0,
            energy_j: 0.0,
            finite: true,
        };
        for (handle, radius) in self.bodies.iter().zip(&self.body_radius_m) {
            let Some(body) = self.world.bodies.get(*handle) else {
                continue;
            };
            if !body.is_dynamic() {
                continue;
            }
            let v = f64::from(body.linvel().length());
            let w = f64::from(body.angvel().length());
            let com = body.center_of_mass();
            state.finite &=
                v.is_finite() && w.is_finite() && com.is_finite() && body.rotation().is_finite();
            state.max_point_speed_m_per_s = state.max_point_speed_m_per_s.max(v + w * radius);
            state.energy_j += f64::from(body.kinetic_energy())
                + f64::from(body.mass()) * gravity * f64::from(com.z);
        }
        if !state.max_point_speed_m_per_s.is_finite() {
            state.finite = false;
        }
        state
    }
}

/// Mass properties of a part for the engine: mass, centre of mass and full inertia tensor, all in
/// the object frame (the body frame at rest).
fn mass_properties(part: &uniphys_types::PartRecord) -> SimulateResult<MassProperties> {
    let mass_kg = part.mass.mass_kg.value;
    let bad = |reason: String| SimulateError::MassProperties {
        part: part.id,
        reason,
    };
    if !(mass_kg.is_finite() && mass_kg > 0.0) {
        return Err(bad(format!("mass {mass_kg} kg is not positive")));
    }
    let com = DVec3::from_array(part.mass.com_in_object_m);
    let tensor = part.mass.inertia_about_com_kg_m2;
    if !(com.is_finite() && tensor.iter().flatten().all(|v| v.is_finite())) {
        return Err(bad("centre of mass or inertia is not finite".into()));
    }
    let rows = tensor.map(|r| r.map(|v| v as Real));
    // `Matrix` is column-major; the record is row-major and symmetric.
    let inertia = Matrix::from_cols_array_2d(&rows).transpose();
    Ok(MassProperties::with_inertia_matrix(
        com.as_vec3(),
        mass_kg as Real,
        inertia,
    ))
}
