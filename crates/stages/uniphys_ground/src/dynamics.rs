//! Passive joint dynamics derived from the moving parts' inertia.
//!
//! Rule `joint_dynamics_from_inertia`: viscous damping with a one-second time constant,
//! `damping = I_axis / 1 s` (rotational, N m s/rad) or `m / 1 s` (prismatic, N s/m), where
//! `I_axis` is the moment of inertia of the moving subtree about the joint axis; dry friction
//! of 1 % of the subtree's weight times its lever arm (rotational) or of its weight (prismatic).
//! A joint without stops (a knob, a dial, a wheel) has no limit to rest against, so its dry
//! friction holds the subtree's largest gravity torque, with a margin ([`holding_friction`]):
//! a knob whose centre of mass sits a millimetre off its axis stays where it is turned instead
//! of swinging round like a pendulum, as its shaft's friction and detents keep it in a real one.

use uniphys_geometry::{DMat3, DVec3};

/// Time constant of the viscous damping, seconds.
pub const DAMPING_TIME_CONSTANT_SECS: f64 = 1.0;
/// Dry friction as a fraction of the moving subtree's weight.
pub const FRICTION_FRACTION_OF_WEIGHT: f64 = 0.01;
/// Shortest damping time constant (inertia / damping) an exported joint may have: two steps of
/// PyBullet's default 240 Hz. Explicit integrators blow up when damping removes a body's momentum
/// in less than a step (a 0.5 N m s/rad damper on a 4e-4 kg m^2 wrist link does).
pub const MIN_DAMPING_TIME_CONSTANT_SECS: f64 = 2.0 / 240.0;
const GRAVITY_M_PER_S2: f64 = 9.81;

/// Mass, centre of mass and inertia about the centre of mass of a rigid group, object frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMass {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Centre of mass, metres.
    pub com: DVec3,
    /// Inertia about `com`, kg m^2.
    pub inertia_about_com_kg_m2: DMat3,
}

impl RigidMass {
    /// Combines rigid masses into one (parallel-axis theorem).
    #[must_use]
    pub fn combine(items: &[RigidMass]) -> RigidMass {
        let mass_kg: f64 = items.iter().map(|r| r.mass_kg).sum();
        if mass_kg <= 0.0 {
            return RigidMass {
                mass_kg: 0.0,
                com: DVec3::ZERO,
                inertia_about_com_kg_m2: DMat3::ZERO,
            };
        }
        let com = items.iter().map(|r| r.com * r.mass_kg).sum::<DVec3>() / mass_kg;
        let inertia = items.iter().fold(DMat3::ZERO, |acc, r| {
            acc + r.inertia_about_com_kg_m2 + parallel_axis(r.mass_kg, r.com - com)
        });
        RigidMass {
            mass_kg,
            com,
            inertia_about_com_kg_m2: inertia,
        }
    }

    /// Moment of inertia about the line through `pivot` along the unit `axis`.
    #[must_use]
    pub fn moment_about_axis(&self, axis: DVec3, pivot: DVec3) -> f64 {
        let lever = (self.com - pivot).reject_from_normalized(axis);
        axis.dot(self.inertia_about_com_kg_m2 * axis) + self.mass_kg * lever.length_squared()
    }
}

/// The inertia of a point mass `m` at offset `r`: `m (|r|^2 I - r r^T)`.
#[must_use]
pub fn parallel_axis(mass_kg: f64, r: DVec3) -> DMat3 {
    let outer = DMat3::from_cols(r * r.x, r * r.y, r * r.z);
    (DMat3::IDENTITY * r.length_squared() - outer) * mass_kg
}

/// Damping and dry friction of a joint moving `moving` about/along `axis` through `pivot`.
#[must_use]
pub fn joint_dynamics(
    moving: &RigidMass,
    axis: DVec3,
    pivot: DVec3,
    rotational: bool,
) -> (f64, f64) {
    if rotational {
        let lever_m = (moving.com - pivot).reject_from_normalized(axis).length();
        (
            moving.moment_about_axis(axis, pivot) / DAMPING_TIME_CONSTANT_SECS,
            FRICTION_FRACTION_OF_WEIGHT * moving.mass_kg * GRAVITY_M_PER_S2 * lever_m,
        )
    } else {
        (
            moving.mass_kg / DAMPING_TIME_CONSTANT_SECS,
            FRICTION_FRACTION_OF_WEIGHT * moving.mass_kg * GRAVITY_M_PER_S2,
        )
    }
}

/// How far a joint without stops holds more than its largest gravity torque.
pub const HOLDING_MARGIN: f64 = 1.2;

/// Dry friction, N m, that holds `moving` still about the line through `pivot` along the unit
/// `axis` at any angle: [`HOLDING_MARGIN`] times the largest gravity torque about it, its weight
/// times its lever arm times how far the axis is from vertical (+z up; none about a vertical
/// axis).
#[must_use]
pub fn holding_friction(moving: &RigidMass, axis: DVec3, pivot: DVec3) -> f64 {
    let lever_m = (moving.com - pivot).reject_from_normalized(axis).length();
    let off_vertical = axis.cross(DVec3::Z).length();
    HOLDING_MARGIN * moving.mass_kg * GRAVITY_M_PER_S2 * lever_m * off_vertical
}

/// The largest damping that keeps the joint's time constant at or above
/// [`MIN_DAMPING_TIME_CONSTANT_SECS`].
#[must_use]
pub fn max_stable_damping(moving: &RigidMass, axis: DVec3, pivot: DVec3, rotational: bool) -> f64 {
    let inertia = if rotational {
        moving.moment_about_axis(axis, pivot)
    } else {
        moving.mass_kg
    };
    inertia / MIN_DAMPING_TIME_CONSTANT_SECS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn door_moment_about_its_edge_matches_the_slab_formula() {
        // Thin slab of mass 3 kg, width 0.6 m along x, hinge along z at x = -0.3: I = m w^2 / 3.
        let w: f64 = 0.6;
        let m = 3.0;
        let slab = RigidMass {
            mass_kg: m,
            com: DVec3::ZERO,
            inertia_about_com_kg_m2: DMat3::from_diagonal(DVec3::new(
                0.0,
                m * w * w / 12.0,
                m * w * w / 12.0,
            )),
        };
        let i = slab.moment_about_axis(DVec3::Z, DVec3::new(-0.3, 0.0, 0.0));
        assert!((i - m * w * w / 3.0).abs() < 1e-12);
        let (damping, friction) = joint_dynamics(&slab, DVec3::Z, DVec3::new(-0.3, 0.0, 0.0), true);
        assert!((damping - i).abs() < 1e-12);
        assert!((friction - 0.01 * m * 9.81 * 0.3).abs() < 1e-12);
    }

    #[test]
    fn a_knob_off_balance_is_held_and_a_vertical_axis_needs_no_hold() {
        // 20 g knob, centre of mass 1 mm off its horizontal axis.
        let knob = RigidMass {
            mass_kg: 0.02,
            com: DVec3::new(0.0, 0.001, 0.0),
            inertia_about_com_kg_m2: DMat3::from_diagonal(DVec3::splat(1e-6)),
        };
        let gravity_torque = 0.02 * 9.81 * 0.001;
        let hold = holding_friction(&knob, DVec3::X, DVec3::ZERO);
        assert!((hold - HOLDING_MARGIN * gravity_torque).abs() < 1e-12);
        let (_, rule) = joint_dynamics(&knob, DVec3::X, DVec3::ZERO, true);
        assert!(rule < gravity_torque, "the weight rule alone lets it swing");
        assert!(holding_friction(&knob, DVec3::Z, DVec3::ZERO).abs() < 1e-15);
    }

    #[test]
    fn stable_damping_keeps_two_pybullet_steps_of_time_constant() {
        // A light wrist link: I = 4e-4 kg m^2 about its axis through the centre of mass.
        let link = RigidMass {
            mass_kg: 0.36,
            com: DVec3::ZERO,
            inertia_about_com_kg_m2: DMat3::from_diagonal(DVec3::splat(4e-4)),
        };
        let max = max_stable_damping(&link, DVec3::Z, DVec3::ZERO, true);
        assert!((max - 4e-4 * 120.0).abs() < 1e-12);
        assert!(max < 0.5, "the input's 0.5 N m s/rad must be lowered");
        assert!(
            (max_stable_damping(&link, DVec3::Z, DVec3::ZERO, false) - 0.36 * 120.0).abs() < 1e-9
        );
    }

    #[test]
    fn combining_two_point_masses_uses_the_parallel_axis_theorem() {
        let a = RigidMass {
            mass_kg: 1.0,
            com: DVec3::new(-1.0, 0.0, 0.0),
            inertia_about_com_kg_m2: DMat3::ZERO,
        };
        let b = RigidMass {
            mass_kg: 1.0,
            com: DVec3::new(1.0, 0.0, 0.0),
            inertia_about_com_kg_m2: DMat3::ZERO,
        };
        let c = RigidMass::combine(&[a, b]);
        assert_eq!(c.com, DVec3::ZERO);
        assert!((c.inertia_about_com_kg_m2.z_axis.z - 2.0).abs() < 1e-12);
        assert!(c.inertia_about_com_kg_m2.x_axis.x.abs() < 1e-12);
    }
}
