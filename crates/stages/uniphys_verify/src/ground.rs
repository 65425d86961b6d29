//! The ground an object rests on. The service frame is Z up with the asset's lowest point on
//! z = 0, but an asset given turned over (onto a corner or an edge) touches that plane at a
//! point or along a line: it does not rest there, and the plane says nothing about gravity.

use uniphys_geometry::{Aabb, DVec3, convex_outline, outline_area};

/// Samples within this fraction of the object's diagonal of its lowest point touch the ground.
pub const GROUND_TOUCH_FRACTION: f64 = 0.01;
/// A part stands on the ground when its samples touching it span at least this share of its
/// plan (its box seen from above): a base, a body's bottom or its feet, a wheel's tread; a part
/// of an object turned onto a corner or an edge touches it at a point or along a line.
pub const FOOTPRINT_SHARE_MIN: f64 = 0.1;

/// Whether a part with surface samples `points` stands on the ground at `floor_z_m` (its lowest
/// point at rest plus the touching distance): the outline of its samples at or below it covers
/// [`FOOTPRINT_SHARE_MIN`] of its plan.
#[must_use]
pub fn stands_on_ground(points: &[DVec3], floor_z_m: f64) -> bool {
    let footprint: Vec<[f64; 2]> = points
        .iter()
        .filter(|p| p.z <= floor_z_m)
        .map(|p| [p.x, p.y])
        .collect();
    let plan = Aabb::from_points(points);
    let plan_m2 = (plan.max.x - plan.min.x) * (plan.max.y - plan.min.y);
    plan_m2 > 0.0 && outline_area(&convex_outline(&footprint)) >= FOOTPRINT_SHARE_MIN * plan_m2
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_4;
    use uniphys_geometry::DQuat;

    /// Points on a grid filling the unit cube standing on z = 0 around the z axis.
    fn cube() -> Vec<DVec3> {
        let mut out = Vec::new();
        for i in 0..=5 {
            for j in 0..=5 {
                for k in 0..=5 {
                    let t = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) / 5.0;
                    out.push(t - DVec3::new(0.5, 0.5, 0.0));
                }
            }
        }
        out
    }

    #[test]
    fn a_box_stands_on_its_face_and_not_on_a_corner_or_above_the_ground() {
        assert!(stands_on_ground(&cube(), 0.01));
        // Turned 45 degrees about x and then about y, it touches the ground at one corner.
        let turn = DQuat::from_rotation_y(0.6155) * DQuat::from_rotation_x(FRAC_PI_4);
        let turned: Vec<DVec3> = cube().iter().map(|p| turn * *p).collect();
        let floor = turned.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        assert!(!stands_on_ground(&turned, floor + 0.01));
        assert!(!stands_on_ground(&cube(), -0.01));
    }
}
