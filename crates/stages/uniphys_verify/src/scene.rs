//! The parts of an asset prepared for sweeps: surface samples and convex colliders.

use std::collections::{BTreeSet, HashMap};
use std::sync::{Arc, Mutex};

use uniphys_geometry::{Aabb, DVec3, TriMesh, box_axes, sample_points};
use uniphys_types::{Joint, PartId};

use crate::crossing::Surfaces;
use crate::fit::{round_axis, spin_residual};
use crate::ground::{GROUND_TOUCH_FRACTION, stands_on_ground};
use crate::held::mean;
use crate::part_box::PartBox;
use crate::penetration::Colliders;
use crate::{VerifyError, VerifyResult};

/// Part geometry in the object frame, ready for sweeps.
pub struct Scene {
    /// Surface samples per part, metres.
    pub(crate) samples: Vec<Vec<DVec3>>,
    pub(crate) colliders: Colliders,
    /// The parts' own triangle surfaces, for crossings.
    pub(crate) surfaces: Surfaces,
    /// Surface area of each part, m^2.
    pub(crate) areas_m2: Vec<f64>,
    /// Diagonal of the whole object's bounds, metres: the unit of every relative threshold.
    pub diagonal_m: f64,
    /// Centre of the whole object's bounds, object frame, metres.
    pub centre_m: DVec3,
    /// Height of the ground the object stands on: its lowest point at rest (the service frame
    /// is Z up with the asset resting on the ground), metres; `None` when no part stands on it
    /// ([`stands_on_ground`]: an object turned onto a corner or an edge).
    pub ground_z_m: Option<f64>,
    /// Whether each part stands on that ground.
    standing: Vec<bool>,
    /// The line each group of parts (its indices as the sweep is given them) is round about,
    /// found on first use: the sweeps of a joint's variants and of a grounder's hypotheses
    /// would otherwise search it again each time.
    round_lines: Mutex<HashMap<Vec<usize>, Option<RoundLine>>>,
    /// Boxes of part sets already found ([`Self::part_box`]).
    part_boxes: Mutex<HashMap<Vec<usize>, Arc<PartBox>>>,
}

/// A group of parts whose roundness residual about each of its box axes through its centroid is
/// above this share of its diagonal is round about no line (a round part's box axes run along
/// and across its axis: a knob whose box is tilted a few degrees by its pointer is within 0.05).
const ROUND_SCREEN_RESIDUAL_MAX: f64 = 0.1;

/// A line a group of parts is round about: `(direction, a point on it, roundness residual)`
/// (see `fit::round_axis`).
pub(crate) type RoundLine = (DVec3, DVec3, f64);

impl Scene {
    /// Samples `samples_per_part` surface points of each part (seeded by the part index),
    /// builds its convex colliders (`colliders[part]`, closed convex hulls) and a hierarchy over
    /// its own triangles.
    ///
    /// Errors: meshes and colliders of different lengths; an empty or flat object.
    pub fn new(
        meshes: &[TriMesh],
        colliders: &[Vec<TriMesh>],
        samples_per_part: usize,
    ) -> VerifyResult<Self> {
        if meshes.len() != colliders.len() {
            return Err(VerifyError::PartCountMismatch {
                parts: meshes.len(),
                meshes: meshes.len(),
                colliders: colliders.len(),
            });
        }
        let bounds = meshes.iter().fold(Aabb::EMPTY, |a, m| a.union(m.bounds()));
        let diagonal_m = bounds.diagonal();
        if !(diagonal_m.is_finite() && diagonal_m > 0.0) {
            return Err(VerifyError::InvalidParameter(
                "the object has no extent; nothing to verify".to_owned(),
            ));
        }
        let samples: Vec<Vec<DVec3>> = meshes
            .iter()
            .enumerate()
            .map(|(i, m)| sample_points(m, samples_per_part, 0x5eed_0000 + i as u64))
            .collect();
        let floor_z_m = bounds.min.z + GROUND_TOUCH_FRACTION * diagonal_m;
        let standing: Vec<bool> = samples
            .iter()
            .map(|points| stands_on_ground(points, floor_z_m))
            .collect();
        let ground_z_m = standing.contains(&true).then_some(bounds.min.z);
        Ok(Self {
            samples,
            colliders: Colliders::new(colliders, bounds.center()),
            surfaces: Surfaces::new(meshes, bounds.center()),
            areas_m2: meshes.iter().map(TriMesh::area).collect(),
            diagonal_m,
            centre_m: bounds.center(),
            ground_z_m,
            standing,
            round_lines: Mutex::new(HashMap::new()),
            part_boxes: Mutex::new(HashMap::new()),
        })
    }

    /// Number of parts.
    #[must_use]
    pub fn part_count(&self) -> usize {
        self.samples.len()
    }

    /// Distance from `point` (object frame) to the own triangles of `part`, metres (infinite for
    /// a part without a surface).
    #[must_use]
    pub fn distance_to_surface_m(&self, part: usize, point: DVec3) -> f64 {
        self.surfaces.distance_m(part, point)
    }

    /// Surface area of `part`'s own triangles, m^2 (0 for a part index out of range).
    #[must_use]
    pub fn area_m2(&self, part: usize) -> f64 {
        self.areas_m2.get(part).copied().unwrap_or(0.0)
    }

    /// Whether `part` stands on the ground the object rests on ([`stands_on_ground`]).
    #[must_use]
    pub fn stands_on_ground(&self, part: usize) -> bool {
        self.standing.get(part).copied().unwrap_or(false)
    }

    /// The line the parts `parts` (their samples `points`, as [`Self::points_of`] gives
    /// them) are round about, searched from their box axes, if they are round about one.
    pub(crate) fn round_line(&self, parts: &[usize], points: &[DVec3]) -> Option<RoundLine> {
        remembered(&self.round_lines, parts, || {
            let axes = box_axes(points);
            // A part far from round about each of its box axes through its centroid is round
            // about no line near them: the pattern search, hundreds of turns of the samples, is
            // skipped.
            let centroid = mean(points);
            let nearly_round = axes
                .iter()
                .any(|&a| spin_residual(points, a, centroid) <= ROUND_SCREEN_RESIDUAL_MAX);
            if nearly_round {
                round_axis(points, &axes)
            } else {
                None
            }
        })
    }

    /// The box of the parts `parts` (their samples `points`, as [`Self::points_of`] gives them),
    /// found once per scene.
    pub(crate) fn part_box(&self, parts: &[usize], points: &[DVec3]) -> Arc<PartBox> {
        remembered(&self.part_boxes, parts, || Arc::new(PartBox::of(points)))
    }

    /// A scene of hand-built `meshes`, each its own single convex collider, with
    /// `samples_per_part` samples per part (for unit tests of the sweep's measures).
    #[cfg(test)]
    pub(crate) fn of_convex_parts(meshes: &[TriMesh], samples_per_part: usize) -> Self {
        let colliders: Vec<Vec<TriMesh>> = meshes.iter().map(|m| vec![m.clone()]).collect();
        Self::new(meshes, &colliders, samples_per_part).expect("a scene of hand-built parts")
    }

    /// The parts that stay still while `moving` moves: every part not in it, in order.
    #[must_use]
    pub fn still_parts(&self, moving: &[usize]) -> Vec<usize> {
        (0..self.part_count())
            .filter(|p| !moving.contains(p))
            .collect()
    }

    /// Surface samples of the given parts, concatenated.
    #[must_use]
    pub fn points_of(&self, parts: &[usize]) -> Vec<DVec3> {
        parts
            .iter()
            .flat_map(|&p| self.samples[p].iter().copied())
            .collect()
    }
}

/// The value kept in `known` for `parts`, or `compute()`'s, kept for the next caller (a lock
/// poisoned by a panic elsewhere only costs the cache).
fn remembered<V: Clone>(
    known: &Mutex<HashMap<Vec<usize>, V>>,
    parts: &[usize],
    compute: impl FnOnce() -> V,
) -> V {
    if let Some(value) = known.lock().ok().and_then(|m| m.get(parts).cloned()) {
        return value;
    }
    let value = compute();
    if let Ok(mut m) = known.lock() {
        m.insert(parts.to_vec(), value.clone());
    }
    value
}

/// The parts that move with `joint.child`: the child and everything below it in `joints`,
/// sorted.
#[must_use]
pub fn moving_group(joints: &[Joint], child: PartId) -> Vec<usize> {
    let mut out = BTreeSet::from([child.0 as usize]);
    let mut stack = vec![child];
    while let Some(p) = stack.pop() {
        for j in joints.iter().filter(|j| j.parent == p) {
            if out.insert(j.child.0 as usize) {
                stack.push(j.child);
            }
        }
    }
    out.into_iter().collect()
}
