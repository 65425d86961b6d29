//! Where a hinged sheet shuts: a door, a lid or a laptop's screen covers the opening of its
//! parent at one end of its travel, lying against it. A hinge that turns a sheet which is open
//! at rest only further from its parent (a screen tipped back onto the table) never shuts it.

use uniphys_geometry::{Aabb, DVec3};

use crate::motion::JointMotion;
use crate::scene::Scene;

/// A sheet sample this close to its parent, as a share of the moving parts' diagonal, lies
/// against it.
const SHUT_TOUCH_FRACTION: f64 = 0.05;
/// Most sheet samples measured per pose (every k-th of the part's).
const SHUT_SAMPLES_MAX: usize = 400;

/// The largest share of the `sheet`'s samples lying against `parent` at rest or at either end
/// of the range `(lower, upper)` of `motion`; `moving` are the samples of the whole moving group
/// (their diagonal sets the touch distance).
pub(crate) fn shut_share(
    scene: &Scene,
    motion: &JointMotion,
    (lower, upper): (f64, f64),
    sheet: &[DVec3],
    moving: &[DVec3],
    parent: usize,
) -> f64 {
    if sheet.is_empty() {
        return 0.0;
    }
    let touch_m = SHUT_TOUCH_FRACTION * Aabb::from_points(moving).diagonal();
    let every = sheet.len().div_ceil(SHUT_SAMPLES_MAX);
    let samples: Vec<DVec3> = sheet.iter().step_by(every).copied().collect();
    [lower, 0.0, upper]
        .into_iter()
        .map(|q| {
            let to_object = motion.object_from_moved(q);
            let against = samples
                .iter()
                .filter(|p| {
                    scene
                        .surfaces
                        .distance_m(parent, to_object.transform_point3(**p))
                        <= touch_m
                })
                .count();
            against as f64 / samples.len() as f64
        })
        .fold(0.0, f64::max)
}
