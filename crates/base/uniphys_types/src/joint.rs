use serde::{Deserialize, Serialize};

use crate::{PartId, Provenance};

/// The kind of a joint between two parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// Rotation about an axis within limits (dataset movement type C).
    Revolute,
    /// Unlimited rotation about an axis.
    Continuous,
    /// Translation along an axis within limits (dataset movement type B).
    Prismatic,
    /// Rigid attachment (dataset movement type D).
    Fixed,
}

impl JointKind {
    /// Whether the joint has a degree of freedom.
    #[must_use]
    pub fn is_movable(self) -> bool {
        !matches!(self, Self::Fixed)
    }

    /// Whether the joint must carry limits (revolute and prismatic).
    #[must_use]
    pub fn needs_limits(self) -> bool {
        matches!(self, Self::Revolute | Self::Prismatic)
    }

    /// The kind's name as serialised (`revolute`, `continuous`, `prismatic`, `fixed`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Revolute => "revolute",
            Self::Continuous => "continuous",
            Self::Prismatic => "prismatic",
            Self::Fixed => "fixed",
        }
    }

    /// Dataset movement type letter: `B` prismatic, `C` revolute or continuous, `D` fixed.
    #[must_use]
    pub fn movement_type(self) -> char {
        match self {
            Self::Prismatic => 'B',
            Self::Revolute | Self::Continuous => 'C',
            Self::Fixed => 'D',
        }
    }
}

/// Joint limits: radians for rotational joints, metres for prismatic ones.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointLimits {
    /// Lower bound (rad or m).
    pub lower: f64,
    /// Upper bound (rad or m).
    pub upper: f64,
}

/// A joint connecting a child part to its parent part.
///
/// Axis and pivot are expressed in the object frame (Z-up, metres) at the rest configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Joint {
    /// Unique joint name.
    pub name: String,
    /// Joint kind.
    pub kind: JointKind,
    /// The part the joint is attached to.
    pub parent: PartId,
    /// The part the joint moves.
    pub child: PartId,
    /// Unit axis of motion in the object frame.
    pub axis_in_object: [f64; 3],
    /// A point on the axis (the pivot) in the object frame, metres.
    pub pivot_in_object_m: [f64; 3],
    /// Limits; required for revolute and prismatic joints.
    pub limits: Option<JointLimits>,
    /// Viscous damping: N m s/rad (rotational) or N s/m (prismatic).
    pub damping: f64,
    /// Dry friction: N m (rotational) or N (prismatic).
    pub friction: f64,
    /// Parts that move rigidly with `child` (its motion-coupled group, `child` excluded).
    pub coupled_parts: Vec<PartId>,
    /// Where the joint hypothesis came from.
    pub provenance: Provenance,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kind_is_named_as_it_serialises() {
        for kind in [
            JointKind::Revolute,
            JointKind::Continuous,
            JointKind::Prismatic,
            JointKind::Fixed,
        ] {
            let serialised = serde_json::to_value(kind).expect("a kind serialises");
            assert_eq!(serialised, kind.as_str());
        }
    }
}
