//! The answers the prompts ask for, as serde types. The model's JSON is checked field by field by
//! [`crate::validate`] (which collects every violation) before it becomes one of these; they are
//! also what test fixtures and the benchmark's responder serialise.
//!
//! Quantities keep the unit strings the model wrote (`"0.7 g/cm^3"`, `"0-30 cm"`); the
//! validator guarantees they parse ([`crate::quantities`]), and [`crate::convert`] turns them
//! into SI values.

use serde::{Deserialize, Serialize};

/// The answer to the properties request: the object and every part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PropertiesAnswer {
    /// Short object name.
    pub object_name: String,
    /// Object category.
    pub category: String,
    /// `"L*W*H cm"`.
    pub dimensions: String,
    /// `"12.5 kg"`.
    pub mass: String,
    /// One entry per part, labels 1..n.
    pub parts: Vec<PartAnswer>,
}

/// One part of the properties answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartAnswer {
    /// Label 1..n: the position of the part's image.
    pub label: u32,
    /// Short part name.
    pub name: String,
    /// `"category/subtype"`.
    pub material: String,
    /// `"0.7 g/cm^3"`.
    pub density: String,
    /// Young's modulus, GPa.
    pub youngs_modulus_gpa: f64,
    /// Vickers hardness, HV.
    pub hardness_hv: f64,
    /// Poisson's ratio, 0 to 0.5.
    pub poisson_ratio: f64,
    /// Friction coefficient, 0 to 2.
    pub friction_coefficient: f64,
    /// 1 (most interacted with) to 10.
    pub affordance_rank: u8,
    /// Whether a hand grasps it.
    pub graspable: bool,
    /// Touching or connected parts.
    pub neighbours: Vec<NeighbourAnswer>,
    /// Text descriptions.
    pub descriptions: DescriptionsAnswer,
}

/// How two parts relate (the reference's movement types).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum MovementType {
    /// The parts only touch.
    A,
    /// One slides relative to the other (prismatic).
    B,
    /// One turns relative to the other (revolute).
    C,
    /// The parts are rigidly joined.
    D,
}

impl MovementType {
    /// Parses `"A"`..`"D"` (case-insensitive, surrounding blanks ignored).
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        match text.trim().to_ascii_uppercase().as_str() {
            "A" => Some(Self::A),
            "B" => Some(Self::B),
            "C" => Some(Self::C),
            "D" => Some(Self::D),
            _ => None,
        }
    }

    /// Whether the relation is a joint with a degree of freedom (B or C).
    #[must_use]
    pub fn is_motion(self) -> bool {
        matches!(self, Self::B | Self::C)
    }
}

/// One neighbour of a part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NeighbourAnswer {
    /// The other part's label.
    pub label: u32,
    /// A, B, C or D.
    pub movement_type: MovementType,
    /// B/C: the part that stays.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent: Option<u32>,
    /// B/C: the part that moves.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub child: Option<u32>,
    /// B/C: damping coefficient.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// B/C: `"0-30 cm"` or `"0-110 degrees"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<String>,
}

/// The four descriptions of a part.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DescriptionsAnswer {
    /// What the part is.
    pub basic: String,
    /// What it is for.
    pub functional: String,
    /// How it moves.
    pub movement: String,
    /// How a hand holds it.
    pub grasp: String,
}

/// The answer to one articulation request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArticulationAnswer {
    /// The model's understanding of the part.
    pub part_description: String,
    /// Why this axis.
    pub axis_description: String,
    /// A colour name of the axis legend.
    pub axis_colour: String,
    /// Along (`Positive`) or against (`Negative`) the chosen axis.
    pub motion_direction: MotionDirection,
    /// Revolute: a colour of the pivot legend or `"average"`; prismatic: `None`.
    #[serde(default)]
    pub pivot: Option<String>,
    /// Free-text justification.
    #[serde(default)]
    pub justification: String,
}

/// Sign of the motion relative to the chosen axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionDirection {
    /// Opening moves along the axis.
    Positive,
    /// Opening moves against the axis: the axis is flipped.
    Negative,
}
