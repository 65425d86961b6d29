//! Geometry-constrained joint choice for one movable part: candidates from its contact with its
//! parent (`uniphys_verify::articulation_candidates`, with the object frame X, Y, Z as the last
//! three axes), the model's answer mapped colour name → candidate index → vector (never by
//! comparing printed vectors), the direction applied, the pivot chosen, limits and damping from
//! the properties answer.

use uniphys_geometry::{DVec3, TriMesh, sample_points};
use uniphys_types::{Joint, JointKind, PartId, Provenance};
use uniphys_verify::{ArticulationCandidates, PatchParams, VerifyResult, articulation_candidates};

use crate::colours::colour_index;
use crate::motion_graph::MovablePart;
use crate::schema::{ArticulationAnswer, MotionDirection};

/// Index of the contact-cluster centroid among the pivots (used for slides).
pub const CENTROID_PIVOT: usize = 5;

/// The joint the answer selects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Choice {
    /// Index of the chosen axis candidate.
    pub axis_index: usize,
    /// Unit axis, flipped when the motion is negative.
    pub axis: DVec3,
    /// Index of the chosen pivot, `None` for `"average"`.
    pub pivot_index: Option<usize>,
    /// The pivot, metres.
    pub pivot_m: DVec3,
}

/// Maps a validated answer onto the candidates: the axis colour's index in `axis_legend`
/// selects the axis (flipped for a negative direction); for a revolute joint the pivot colour's
/// index in `pivot_legend` selects the pivot, `"average"` takes the mean of all of them; a
/// slide takes the contact centroid. `None` if a colour is not in its legend.
#[must_use]
pub fn resolve_choice(
    candidates: &ArticulationCandidates,
    answer: &ArticulationAnswer,
    revolute: bool,
    axis_legend: &[&str],
    pivot_legend: &[&str],
) -> Option<Choice> {
    let axis_index = colour_index(&answer.axis_colour, axis_legend)?;
    let mut axis = candidates.axes.get(axis_index)?.normalize();
    if answer.motion_direction == MotionDirection::Negative {
        axis = -axis;
    }
    let centroid = *candidates.pivots.get(CENTROID_PIVOT)?;
    let (pivot_index, pivot_m) = if revolute {
        let text = answer.pivot.as_deref()?;
        if text.trim().eq_ignore_ascii_case("average") {
            let n = candidates.pivots.len().max(1) as f64;
            (None, candidates.pivots.iter().sum::<DVec3>() / n)
        } else {
            let i = colour_index(text, pivot_legend)?;
            (Some(i), *candidates.pivots.get(i)?)
        }
    } else {
        (Some(CENTROID_PIVOT), centroid)
    };
    Some(Choice {
        axis_index,
        axis,
        pivot_index,
        pivot_m,
    })
}

/// Candidates of `movable`: its group's surface samples against its parent's; if the group does
/// not touch its parent, against every other part (as the reference does).
///
/// # Errors
/// No contact with any other part.
pub fn candidates_for(
    movable: &MovablePart,
    meshes: &[TriMesh],
    object_diagonal_m: f64,
    points_per_part: usize,
    seed: u64,
) -> VerifyResult<ArticulationCandidates> {
    let index = |label: u32| (label as usize).saturating_sub(1);
    let samples = |i: usize| {
        meshes
            .get(i)
            .map(|m| sample_points(m, points_per_part, seed ^ (i as u64).wrapping_mul(0x9E37)))
            .unwrap_or_default()
    };
    let moving: Vec<DVec3> = movable
        .group
        .iter()
        .flat_map(|&l| samples(index(l)))
        .collect();
    let frame = [DVec3::X, DVec3::Y, DVec3::Z];
    let params = PatchParams::default();
    let parent = samples(index(movable.parent));
    articulation_candidates(&moving, &parent, frame, object_diagonal_m, &params, seed).or_else(
        |_| {
            let others: Vec<DVec3> = (0..meshes.len())
                .filter(|i| !movable.group.iter().any(|&l| index(l) == *i))
                .flat_map(samples)
                .collect();
            articulation_candidates(&moving, &others, frame, object_diagonal_m, &params, seed)
        },
    )
}

/// The joint of `movable` with the chosen axis and pivot, the answer's limits and damping.
#[must_use]
pub fn joint(movable: &MovablePart, choice: &Choice, provenance: Provenance) -> Joint {
    let id = |label: u32| PartId(label.saturating_sub(1));
    Joint {
        name: String::new(),
        kind: movable.kind,
        parent: id(movable.parent),
        child: id(movable.label),
        axis_in_object: choice.axis.to_array(),
        pivot_in_object_m: choice.pivot_m.to_array(),
        limits: Some(movable.limits),
        damping: movable.damping,
        friction: 0.0,
        coupled_parts: movable
            .group
            .iter()
            .filter(|&&l| l != movable.label)
            .map(|&l| id(l))
            .collect(),
        provenance,
    }
}

/// A fixed joint attaching `child` to `parent` at the child's bounds centre.
#[must_use]
pub fn fixed_joint(parent: u32, child: u32, anchor_m: DVec3, provenance: Provenance) -> Joint {
    Joint {
        name: String::new(),
        kind: JointKind::Fixed,
        parent: PartId(parent.saturating_sub(1)),
        child: PartId(child.saturating_sub(1)),
        axis_in_object: [1.0, 0.0, 0.0],
        pivot_in_object_m: anchor_m.to_array(),
        limits: None,
        damping: 0.0,
        friction: 0.0,
        coupled_parts: Vec::new(),
        provenance,
    }
}
