//! Running statistics of one joint's coordinate over a phase of the simulation.

/// What one joint did during a phase, accumulated step by step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct JointTrace {
    /// Coordinate at the start of the phase.
    pub q_start: f64,
    /// Latest coordinate.
    pub q_end: f64,
    /// Latest velocity.
    pub qd_end: f64,
    /// Largest `|q - q_start|`.
    pub max_drift: f64,
    /// Largest `|qd|`.
    pub max_speed: f64,
    /// Sign of `q - q_start` when the drift first exceeded the tolerance (0 if it never did).
    pub first_move_sign: f64,
    /// Velocity reversals between speeds above the settle speed (swings and bounces).
    pub reversals: u32,
    /// Whether every sample was finite.
    pub finite: bool,
    last_significant_sign: f64,
}

impl JointTrace {
    /// A trace starting at coordinate `q_start`.
    pub fn new(q_start: f64) -> Self {
        Self {
            q_start,
            q_end: q_start,
            qd_end: 0.0,
            max_drift: 0.0,
            max_speed: 0.0,
            first_move_sign: 0.0,
            reversals: 0,
            finite: q_start.is_finite(),
            last_significant_sign: 0.0,
        }
    }

    /// Adds one sample. `tolerance` decides when the joint "moved"; `settle_speed` which
    /// velocities count for reversals.
    pub fn record(&mut self, q: f64, qd: f64, tolerance: f64, settle_speed: f64) {
        if !(q.is_finite() && qd.is_finite()) {
            self.finite = false;
            return;
        }
        self.q_end = q;
        self.qd_end = qd;
        let drift = q - self.q_start;
        self.max_drift = self.max_drift.max(drift.abs());
        self.max_speed = self.max_speed.max(qd.abs());
        if self.first_move_sign == 0.0 && drift.abs() > tolerance {
            self.first_move_sign = drift.signum();
        }
        if qd.abs() > settle_speed {
            let sign = qd.signum();
            if self.last_significant_sign != 0.0 && sign != self.last_significant_sign {
                self.reversals += 1;
            }
            self.last_significant_sign = sign;
        }
    }
}
