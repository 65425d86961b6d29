//! Live progress of a job's stages, for the dashboard (ephemeral: it expires).

use serde::{Deserialize, Serialize};

use crate::error::{HintsError, HintsResult};

/// How far one stage of one job has come.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    /// Done fraction, 0 to 1 inclusive.
    pub fraction: f64,
    /// A short human-readable note ("decomposing part 3 of 7").
    pub message: String,
}

impl Progress {
    /// Progress at `fraction` with `message`.
    pub fn new(fraction: f64, message: impl Into<String>) -> Self {
        Self {
            fraction,
            message: message.into(),
        }
    }

    /// Checks the fraction is a number in 0..=1.
    pub(crate) fn validate(&self) -> HintsResult<()> {
        if (0.0..=1.0).contains(&self.fraction) {
            Ok(())
        } else {
            Err(HintsError::InvalidArgument(format!(
                "progress fraction {} is outside 0..=1",
                self.fraction
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fraction_must_be_in_unit_interval() {
        assert!(Progress::new(0.0, "").validate().is_ok());
        assert!(Progress::new(1.0, "").validate().is_ok());
        assert!(Progress::new(1.5, "").validate().is_err());
        assert!(Progress::new(-0.1, "").validate().is_err());
        assert!(Progress::new(f64::NAN, "").validate().is_err());
    }
}
