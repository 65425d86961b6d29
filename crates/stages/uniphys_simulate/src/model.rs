//! What the check needs to know about each joint before simulating: the moving group, the
//! range, tolerances, the static gravity load at the rest pose and the drive's effort bound. Pure `f64` arithmetic on the record, in the object frame.

use std::f64::consts::PI;

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_types::{AssetRecord, Joint, JointKind};

use crate::DynamicParams;

/// Nominal span of a continuous joint's drive test, rad: it is driven to -pi/2 and +pi/2.
pub(crate) const CONTINUOUS_SPAN_RAD: f64 = PI;

/// The share of the drive speed gravity may take from a velocity servo: its lag is the gravity
/// acceleration over the gain.
pub(crate) const GRAVITY_LAG_FRACTION: f64 = 0.05;

/// The static description of one movable joint.
#[derive(Debug, Clone)]
pub(crate) struct JointModel {
    /// Index into `record.joints`.
    pub joint_index: usize,
    /// Joint name.
    pub name: String,
    /// Joint kind (never `Fixed`).
    pub kind: JointKind,
    /// Lower and upper bound used by the check (the limits, or +-pi/2 for a continuous joint).
    pub lower: f64,
    /// See `lower`.
    pub upper: f64,
    /// Whether the joint has limits in the engine.
    pub limited: bool,
    /// Dry friction, N m or N.
    pub friction: f64,
    /// Generalised gravity force on the joint at the rest pose (signed, along the joint's
    /// positive direction), N m or N.
    pub gravity_load: f64,
    /// Bound on the drive's torque or force, N m or N.
    pub drive_max_effort: f64,
    /// Rate at which the drive corrects a velocity error, 1/s: at least the parameters' gain,
    /// and stiff enough that gravity slows the drive by at most [`GRAVITY_LAG_FRACTION`] of its
    /// speed (a 1 cm lid lift is driven at 1 cm/s; a gain of 1000/s would lose all of it).
    pub drive_gain_per_s: f64,
    /// At-rest drift tolerance, rad or m.
    pub rest_tolerance: f64,
}

impl JointModel {
    /// Range length used for relative tolerances, rad or m.
    pub fn span(&self) -> f64 {
        self.upper - self.lower
    }

    /// Whether the coordinate is a rotation.
    pub fn is_rotational(&self) -> bool {
        self.kind != JointKind::Prismatic
    }

    /// Unit suffix of coordinates: `rad` or `m`.
    pub fn unit(&self) -> &'static str {
        if self.is_rotational() { "rad" } else { "m" }
    }

    /// Unit suffix of efforts: `n_m` or `n`.
    pub fn effort_unit(&self) -> &'static str {
        if self.is_rotational() { "n_m" } else { "n" }
    }

    /// A tolerance on this joint's coordinate: `fraction` of the span, at least `floor_scale`
    /// times the at-rest floor.
    pub fn tolerance(&self, params: &DynamicParams, fraction: f64, floor_scale: f64) -> f64 {
        let floor = if self.is_rotational() {
            params.rest_drift_floor_rad
        } else {
            params.rest_drift_floor_m
        };
        (fraction * self.span()).max(floor_scale * floor)
    }

    /// Distance from `q` to the nearer bound of the range (negative outside it).
    pub fn distance_to_limit(&self, q: f64) -> f64 {
        (q - self.lower).min(self.upper - q)
    }
}

/// Builds the model of every movable joint, in record order.
pub(crate) fn joint_models(
    record: &AssetRecord,
    colliders: &[Vec<TriMesh>],
    params: &DynamicParams,
) -> Vec<JointModel> {
    let gravity = DVec3::new(0.0, 0.0, -params.gravity_m_per_s2);
    record
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.kind.is_movable())
        .map(|(joint_index, joint)| {
            let moving_parts = subtree(record, joint);
            let (lower, upper, limited) = match joint.limits {
                Some(l) if joint.kind.needs_limits() => (l.lower, l.upper, true),
                _ => (-CONTINUOUS_SPAN_RAD / 2.0, CONTINUOUS_SPAN_RAD / 2.0, false),
            };
            let axis = DVec3::from_array(joint.axis_in_object).normalize_or_zero();
            let pivot = DVec3::from_array(joint.pivot_in_object_m);
            let mut mass_kg = 0.0;
            let mut gravity_load = 0.0;
            let mut lever_m: f64 = 0.01;
            for &i in &moving_parts {
                let part = &record.parts[i];
                let m = part.mass.mass_kg.value;
                let com = DVec3::from_array(part.mass.com_in_object_m);
                mass_kg += m;
                let arm = com - pivot;
                if joint.kind == JointKind::Prismatic {
                    gravity_load += axis.dot(m * gravity);
                } else {
                    gravity_load += axis.dot(arm.cross(m * gravity));
                    for p in colliders
                        .get(i)
                        .into_iter()
                        .flatten()
                        .flat_map(|h| &h.positions)
                    {
                        let r = *p - pivot;
                        lever_m = lever_m.max((r - r.dot(axis) * axis).length());
                    }
                }
            }
            let weight_n = mass_kg * params.gravity_m_per_s2;
            // Enough to hold the group's weight twice over at its lever arm, and to overcome the
            // joint's own friction and its damping at the drive speed.
            let span = upper - lower;
            let own =
                joint.friction + joint.damping * params.drive_speed_fraction_of_range_per_s * span;
            let drive_max_effort = if joint.kind == JointKind::Prismatic {
                params.drive_effort_weight_multiple * weight_n + own
            } else {
                params.drive_effort_weight_multiple * weight_n * lever_m + own
            };
            // Gravity's acceleration of the coordinate: g along a slide; about a hinge, at most
            // about g over the group's reach.
            let gravity_acceleration = if joint.kind == JointKind::Prismatic {
                params.gravity_m_per_s2
            } else {
                params.gravity_m_per_s2 / lever_m
            };
            let drive_speed = params.drive_speed_fraction_of_range_per_s * span;
            let drive_gain_per_s = params.drive_velocity_gain_per_s.max(
                gravity_acceleration / (GRAVITY_LAG_FRACTION * drive_speed).max(f64::MIN_POSITIVE),
            );
            let mut model = JointModel {
                joint_index,
                name: joint.name.clone(),
                kind: joint.kind,
                lower,
                upper,
                limited,
                friction: joint.friction,
                gravity_load,
                drive_max_effort,
                drive_gain_per_s,
                rest_tolerance: 0.0,
            };
            model.rest_tolerance =
                model.tolerance(params, params.rest_drift_fraction_of_range, 1.0);
            model
        })
        .collect()
}

/// Positions of `joint.child` and all its descendants in `record.parts`.
fn subtree(record: &AssetRecord, joint: &Joint) -> Vec<usize> {
    let mut ids = vec![joint.child];
    let mut cursor = 0;
    while cursor < ids.len() {
        let parent = ids[cursor];
        ids.extend(
            record
                .joints
                .iter()
                .filter(|j| j.parent == parent)
                .map(|j| j.child),
        );
        cursor += 1;
    }
    let mut positions: Vec<usize> = ids
        .iter()
        .filter_map(|id| record.parts.iter().position(|p| p.id == *id))
        .collect();
    positions.sort_unstable();
    positions.dedup();
    positions
}
