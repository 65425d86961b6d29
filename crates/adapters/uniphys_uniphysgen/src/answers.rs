//! Everything a model server answered about one object, kept so that the answers can be applied
//! later without asking again: the queue's `infer` stage stores them, `ground` applies them.

use serde::{Deserialize, Serialize};

use crate::contract::ObjectAnswer;
use crate::{CoordinateFrame, CoordinateFrameJson, PartAnswers, UniPhysGenError, UniPhysGenResult};

/// Version of [`ModelAnswers`] written by this build; a reader refuses others.
pub const MODEL_ANSWERS_VERSION: u32 = 1;

/// A model server's answers about one object, with the frame they are in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelAnswers {
    /// [`MODEL_ANSWERS_VERSION`] when written by this build.
    pub version: u32,
    /// The server that answered.
    pub base_url: String,
    /// The model frame of the answers (object frame, metres, to the [0, 2] frame).
    pub frame: CoordinateFrameJson,
    /// Each part's centre, object frame, metres, in part order (a pivot is restored near it).
    pub part_centers_in_object_m: Vec<[f64; 3]>,
    /// The physics checkpoint's answers, one per part.
    pub physics: PartAnswers,
    /// The kinematics checkpoint's answers, one per part.
    pub motion: PartAnswers,
    /// The object-level checkpoint that answered.
    pub object_model: String,
    /// Its answer.
    pub object: ObjectAnswer,
}

impl ModelAnswers {
    /// The model frame of the answers.
    #[must_use]
    pub fn coordinate_frame(&self) -> CoordinateFrame {
        CoordinateFrame::from_json(&self.frame)
    }

    /// `self` when it is of this build's version and answers for `parts` parts (a value read
    /// back from the store).
    pub fn checked(self, parts: usize) -> UniPhysGenResult<Self> {
        let unreadable = |reason: String| UniPhysGenError::InvalidAnswer {
            part: "object".to_owned(),
            reason,
        };
        if self.version != MODEL_ANSWERS_VERSION {
            return Err(unreadable(format!(
                "stored answers of version {}, this build reads version {MODEL_ANSWERS_VERSION}",
                self.version
            )));
        }
        let counts = [
            self.part_centers_in_object_m.len(),
            self.physics.parts.len(),
            self.motion.parts.len(),
        ];
        if counts.iter().any(|&n| n != parts) {
            return Err(unreadable(format!(
                "stored answers for {counts:?} parts (centres, physics, motion), the asset has {parts}"
            )));
        }
        Ok(self)
    }
}
