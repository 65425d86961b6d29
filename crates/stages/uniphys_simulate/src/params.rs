//! Parameters of the dynamic check: time stepping, tolerances and the drive.

use crate::{SimulateError, SimulateResult};

/// Parameters of [`crate::check_dynamics`]. [`DynamicParams::default`] is what the pipeline uses.
///
/// Tolerances on a joint coordinate are relative to the joint's range with an absolute floor,
/// so a 3 rad door and a 2 cm button are judged alike; the floors keep tiny ranges from
/// demanding sub-numerical precision.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicParams {
    /// Simulation rate, Hz (one solver step per tick).
    pub rate_hz: f64,
    /// Length of the at-rest test, s.
    pub rest_duration_s: f64,
    /// Gravity along -Z, m/s^2.
    pub gravity_m_per_s2: f64,
    /// At rest, a joint may drift this fraction of its range and still pass.
    pub rest_drift_fraction_of_range: f64,
    /// Absolute floor of the at-rest drift tolerance on a rotational joint, rad.
    pub rest_drift_floor_rad: f64,
    /// Absolute floor of the at-rest drift tolerance on a prismatic joint, m.
    pub rest_drift_floor_m: f64,
    /// A joint that moved is "settled" when its final speed is below this fraction of its range
    /// per second.
    pub settle_speed_fraction_of_range_per_s: f64,
    /// The gravity load must exceed the joint friction by this factor before motion at rest is
    /// blamed on gravity (a warning) rather than on the model (a failure).
    pub gravity_over_friction_margin: f64,
    /// Drive speed toward a limit, as a fraction of the range per second.
    pub drive_speed_fraction_of_range_per_s: f64,
    /// Bound on the drive's force or torque, in multiples of the moving group's weight (times
    /// its lever arm for a rotational joint), on top of the joint's own dry friction and its
    /// damping at the drive speed.
    pub drive_effort_weight_multiple: f64,
    /// Rate at which the drive corrects a velocity error, 1/s (motor damping, mass-independent).
    pub drive_velocity_gain_per_s: f64,
    /// Time allowed to reach each limit, as a multiple of the nominal traverse time (range over
    /// drive speed), plus [`Self::drive_time_slack_s`].
    pub drive_time_multiple: f64,
    /// Constant slack added to each drive's time budget, s.
    pub drive_time_slack_s: f64,
    /// A limit counts as reached within this fraction of the range (with the at-rest floors).
    pub reach_fraction_of_range: f64,
    /// While one joint is driven, every other joint may move this fraction of its own range
    /// (with twice the at-rest floors) and still count as not kicked.
    pub kick_fraction_of_range: f64,
    /// Passive simulation after the drive is released, s.
    pub release_duration_s: f64,
    /// Mechanical energy may grow after release by this fraction of `total weight x object
    /// diagonal` (the integrator is not exactly energy-conserving).
    pub energy_gain_fraction: f64,
    /// No point of any body may move faster than this many object diagonals per second.
    pub max_speed_diagonals_per_s: f64,
    /// Armature (reflected inertia) per joint as seconds times its damping, the value the MJCF
    /// export writes; 0 disables it.
    pub armature_s: f64,
    /// Solver iterations per step.
    pub solver_iterations: usize,
}

impl Default for DynamicParams {
    fn default() -> Self {
        Self {
            rate_hz: 240.0,
            rest_duration_s: 1.0,
            gravity_m_per_s2: 9.81,
            rest_drift_fraction_of_range: 0.02,
            rest_drift_floor_rad: 0.005,
            rest_drift_floor_m: 0.001,
            settle_speed_fraction_of_range_per_s: 0.05,
            gravity_over_friction_margin: 1.05,
            drive_speed_fraction_of_range_per_s: 1.0,
            drive_effort_weight_multiple: 2.0,
            drive_velocity_gain_per_s: 1000.0,
            drive_time_multiple: 3.0,
            drive_time_slack_s: 0.5,
            reach_fraction_of_range: 0.02,
            kick_fraction_of_range: 0.05,
            release_duration_s: 0.5,
            energy_gain_fraction: 0.02,
            max_speed_diagonals_per_s: 10.0,
            armature_s: 0.1,
            solver_iterations: 8,
        }
    }
}

impl DynamicParams {
    /// Time step, s.
    #[must_use]
    pub fn dt_s(&self) -> f64 {
        1.0 / self.rate_hz
    }

    /// Checks that every parameter is finite and in its range.
    pub fn validate(&self) -> SimulateResult<()> {
        let positive = [
            ("rate_hz", self.rate_hz),
            ("rest_duration_s", self.rest_duration_s),
            (
                "rest_drift_fraction_of_range",
                self.rest_drift_fraction_of_range,
            ),
            ("rest_drift_floor_rad", self.rest_drift_floor_rad),
            ("rest_drift_floor_m", self.rest_drift_floor_m),
            (
                "settle_speed_fraction_of_range_per_s",
                self.settle_speed_fraction_of_range_per_s,
            ),
            (
                "gravity_over_friction_margin",
                self.gravity_over_friction_margin,
            ),
            (
                "drive_speed_fraction_of_range_per_s",
                self.drive_speed_fraction_of_range_per_s,
            ),
            (
                "drive_effort_weight_multiple",
                self.drive_effort_weight_multiple,
            ),
            ("drive_velocity_gain_per_s", self.drive_velocity_gain_per_s),
            ("drive_time_multiple", self.drive_time_multiple),
            ("reach_fraction_of_range", self.reach_fraction_of_range),
            ("kick_fraction_of_range", self.kick_fraction_of_range),
            ("release_duration_s", self.release_duration_s),
            ("max_speed_diagonals_per_s", self.max_speed_diagonals_per_s),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(SimulateError::InvalidParams {
                    name,
                    reason: format!("must be finite and > 0, got {value}"),
                });
            }
        }
        let non_negative = [
            ("gravity_m_per_s2", self.gravity_m_per_s2),
            ("drive_time_slack_s", self.drive_time_slack_s),
            ("energy_gain_fraction", self.energy_gain_fraction),
            ("armature_s", self.armature_s),
        ];
        for (name, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SimulateError::InvalidParams {
                    name,
                    reason: format!("must be finite and >= 0, got {value}"),
                });
            }
        }
        if self.solver_iterations == 0 {
            return Err(SimulateError::InvalidParams {
                name: "solver_iterations",
                reason: "must be at least 1".into(),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_a_zero_rate_is_not() {
        assert!(DynamicParams::default().validate().is_ok());
        let bad = DynamicParams {
            rate_hz: 0.0,
            ..DynamicParams::default()
        };
        assert!(matches!(
            bad.validate(),
            Err(SimulateError::InvalidParams {
                name: "rate_hz",
                ..
            })
        ));
    }
}
