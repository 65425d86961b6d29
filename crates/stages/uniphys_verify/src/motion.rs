//! Rigid motion of a joint's moving group at a joint coordinate.

use uniphys_geometry::{DMat4, DQuat, DVec3};
use uniphys_types::{Joint, JointKind};

/// The kinematic content of a joint: kind, unit axis and pivot in the object frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointMotion {
    /// Revolute/continuous rotate, prismatic translates, fixed does not move.
    pub kind: JointKind,
    /// Unit axis in the object frame.
    pub axis_in_object: DVec3,
    /// A point on the axis in the object frame, metres.
    pub pivot_in_object_m: DVec3,
}

impl JointMotion {
    /// The motion of `joint` (its axis normalised).
    #[must_use]
    pub fn of(joint: &Joint) -> Self {
        Self {
            kind: joint.kind,
            axis_in_object: DVec3::from_array(joint.axis_in_object).normalize_or_zero(),
            pivot_in_object_m: DVec3::from_array(joint.pivot_in_object_m),
        }
    }

    /// Rotation part of the motion at `q` (identity for prismatic and fixed joints).
    #[must_use]
    pub fn rotation(&self, q: f64) -> DQuat {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => {
                DQuat::from_axis_angle(self.axis_in_object, q)
            }
            JointKind::Prismatic | JointKind::Fixed => DQuat::IDENTITY,
        }
    }

    /// Translation part of the motion at `q`: `x -> rotation * x + translation`.
    #[must_use]
    pub fn translation_m(&self, q: f64) -> DVec3 {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => {
                self.pivot_in_object_m - self.rotation(q) * self.pivot_in_object_m
            }
            JointKind::Prismatic => self.axis_in_object * q,
            JointKind::Fixed => DVec3::ZERO,
        }
    }

    /// `object_from_moved`: where a point of the moving group at rest goes at coordinate `q`
    /// (radians or metres) measured from the rest pose.
    #[must_use]
    pub fn object_from_moved(&self, q: f64) -> DMat4 {
        DMat4::from_rotation_translation(self.rotation(q), self.translation_m(q))
    }
}

impl JointMotion {
    /// Whether a moving sphere (`centre`, `radius`) moved over the coordinates `range` can come
    /// near a still sphere (`other`, `other_radius`): a broad phase. A turning sphere stays
    /// inside the sphere about the foot of its centre on the axis that contains it; a sliding
    /// one inside the capsule it sweeps.
    #[must_use]
    pub fn may_reach(
        &self,
        centre: DVec3,
        radius: f64,
        range: (f64, f64),
        other: DVec3,
        other_radius: f64,
    ) -> bool {
        let reach = radius + other_radius;
        let axis = self.axis_in_object;
        match self.kind {
            JointKind::Prismatic => {
                let start = centre + axis * range.0;
                let d = axis * (range.1 - range.0);
                let t = if d.length_squared() > 0.0 {
                    ((other - start).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (start + d * t).distance(other) <= reach
            }
            JointKind::Fixed => centre.distance(other) <= reach,
            JointKind::Revolute | JointKind::Continuous => {
                let pivot = self.pivot_in_object_m;
                let foot = pivot + axis * (centre - pivot).dot(axis);
                foot.distance(other) <= centre.distance(foot) + reach
            }
        }
    }
}

/// `steps` evenly spaced coordinates from `lower` to `upper` inclusive (one step: `lower`).
#[must_use]
pub fn sweep_coordinates(lower: f64, upper: f64, steps: usize) -> Vec<f64> {
    match steps {
        0 => Vec::new(),
        1 => vec![lower],
        n => (0..n)
            .map(|i| lower + (upper - lower) * i as f64 / (n - 1) as f64)
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn revolute_turns_about_the_pivot_and_prismatic_translates() {
        let hinge = JointMotion {
            kind: JointKind::Revolute,
            axis_in_object: DVec3::Z,
            pivot_in_object_m: DVec3::new(1.0, 0.0, 0.0),
        };
        let m = hinge.object_from_moved(std::f64::consts::FRAC_PI_2);
        // (2, 0, 0) is 1 m from the pivot along +x; a quarter turn about +z puts it at (1, 1, 0).
        let p = m.transform_point3(DVec3::new(2.0, 0.0, 0.0));
        assert!((p - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-12, "{p}");
        assert!(
            (m.transform_point3(hinge.pivot_in_object_m) - hinge.pivot_in_object_m).length()
                < 1e-12
        );
        let slide = JointMotion {
            kind: JointKind::Prismatic,
            axis_in_object: DVec3::NEG_Y,
            pivot_in_object_m: DVec3::ZERO,
        };
        let p = slide.object_from_moved(0.25).transform_point3(DVec3::ONE);
        assert!((p - DVec3::new(1.0, 0.75, 1.0)).length() < 1e-12);
    }

    #[test]
    fn coordinates_include_both_ends() {
        assert_eq!(
            sweep_coordinates(0.0, 1.0, 5),
            vec![0.0, 0.25, 0.5, 0.75, 1.0]
        );
        assert_eq!(sweep_coordinates(0.3, 1.0, 1), vec![0.3]);
        assert!(sweep_coordinates(0.0, 1.0, 0).is_empty());
    }
}
