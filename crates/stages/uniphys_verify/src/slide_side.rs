//! Which way a short slide goes (reference: real-articulated-objects.md, "Push": a small part
//! protruding from or flush with a face of its parent, moving along that face's normal).
//!
//! A part set into a face of its parent that continues around it on every side (a button, a
//! key) is at its outer stop at rest: it is pressed in, toward its parent. So is a part standing
//! on a broad face of its parent (a knob or a button on an appliance's front): nothing pulls it
//! off. A part that caps its parent's end, with no face of the parent around it and the parent
//! no wider than itself there (a lid on a pot, a cap on a jar), lifts off, away from its parent.
//! All are read at rest, from the parent's own triangles around the part's outline where the two
//! meet and from how far the parent reaches from the part's axis around that level.

use std::f64::consts::TAU;

use uniphys_geometry::{DVec3, projection_range};

use crate::held::{farthest_from_line_m, mean};
use crate::scene::Scene;

/// Directions around the slide's axis in which the parent's surface is looked for.
const DIRECTIONS: usize = 16;
/// The parent is looked for this far from the axis, a multiple of the part's largest distance
/// from it (just outside its outline) ...
const PROBE_RADIUS_RATIO: f64 = 1.3;
/// ... within this much of the part's radius either side of the level where the two touch.
const PROBE_HALF_DEPTH_RATIO: f64 = 0.3;
/// The part's middle must lie at least this share of the parent's extent along the axis from
/// the parent's middle for the slide's away side to be read from them.
const AWAY_OFFSET_FRACTION_MIN: f64 = 0.05;

/// How a short slide's part sits on its parent, measured at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlideSide {
    /// Share of the directions around the axis in which the parent's surface continues just
    /// outside the part's outline, at the level where they touch (1: a face around a button; 0:
    /// a lid capping its parent's end).
    pub surround_share: f64,
    /// +1 when the slide takes the part away from its parent (the part's middle lies on the
    /// positive side of the parent's middle along the travel), -1 toward it, 0 when the two
    /// middles are level along the axis and the side cannot be read.
    pub away: f64,
    /// How far the parent reaches from the part's axis around the level where they touch (the
    /// 95th percentile over its samples within the part's radius of that level along the axis),
    /// over the part's radius: about 1 where the part caps its parent's end (a lid, a cap), tens
    /// for a part on a broad face (a knob on an oven's front); 0 without parent samples there.
    pub parent_reach_ratio: f64,
}

/// Percentile of the parent's reach from the part's axis taken as its reach.
const REACH_PERCENTILE: f64 = 95.0;

/// The side of the short slide along unit `axis` (travel `lower..upper`, the larger side
/// counting) of the `moving` samples on `parent`, where `touching` are the moving samples
/// within contact distance of the parent at rest; `None` without such samples.
pub(crate) fn slide_side(
    scene: &Scene,
    parent: usize,
    moving: &[DVec3],
    touching: &[DVec3],
    axis: DVec3,
    (lower, upper): (f64, f64),
) -> Option<SlideSide> {
    let axis = axis.normalize_or_zero();
    if touching.is_empty() || moving.is_empty() || axis == DVec3::ZERO {
        return None;
    }
    let centre = mean(moving);
    let radius_m = farthest_from_line_m(moving, centre, axis);
    if radius_m <= 0.0 {
        return None;
    }
    let level = (mean(touching) - centre).dot(axis);
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let half_depth = PROBE_HALF_DEPTH_RATIO * radius_m;
    let surrounded = (0..DIRECTIONS)
        .filter(|&k| {
            let angle = TAU * k as f64 / DIRECTIONS as f64;
            let out = u * angle.cos() + v * angle.sin();
            let at = centre + out * (PROBE_RADIUS_RATIO * radius_m) + axis * level;
            scene
                .surfaces
                .crossing(parent, at + axis * half_depth, at - axis * half_depth)
                .is_some()
        })
        .count();
    let parent_points = &scene.samples[parent];
    let offset = (centre - mean(parent_points)).dot(axis);
    let (lo, hi) = projection_range(parent_points, axis);
    let travel_sign = if upper >= -lower { 1.0 } else { -1.0 };
    let away = if offset.abs() >= AWAY_OFFSET_FRACTION_MIN * (hi - lo).max(0.0) {
        travel_sign * offset.signum()
    } else {
        0.0
    };
    let mut reach_m: Vec<f64> = parent_points
        .iter()
        .filter(|p| ((**p - centre).dot(axis) - level).abs() <= radius_m)
        .map(|p| (*p - centre).reject_from_normalized(axis).length())
        .collect();
    let parent_reach_ratio = if reach_m.is_empty() {
        0.0
    } else {
        reach_m.sort_by(f64::total_cmp);
        let rank = (REACH_PERCENTILE / 100.0 * (reach_m.len() - 1) as f64).round() as usize;
        reach_m[rank] / radius_m
    };
    Some(SlideSide {
        surround_share: surrounded as f64 / DIRECTIONS as f64,
        away,
        parent_reach_ratio,
    })
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::TriMesh;

    use super::*;
    use crate::held::touching_samples;

    #[test]
    fn a_button_on_a_panel_is_surrounded_and_pressing_it_goes_toward_the_panel() {
        // A 1 x 1 panel 0.1 thick, a 0.1-wide button standing on the middle of its top face.
        let s = Scene::of_convex_parts(
            &[
                TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.1)),
                TriMesh::cuboid(DVec3::new(0.45, 0.45, 0.1), DVec3::new(0.55, 0.55, 0.13)),
            ],
            1500,
        );
        let moving = s.points_of(&[1]);
        let touch = touching_samples(&s, 0, &moving, 0.005);
        let pressed = slide_side(&s, 0, &moving, &touch, DVec3::Z, (-0.01, 0.0)).expect("side");
        assert_eq!(pressed.surround_share, 1.0);
        assert_eq!(pressed.away, -1.0);
        let pulled = slide_side(&s, 0, &moving, &touch, DVec3::Z, (0.0, 0.01)).expect("side");
        assert_eq!(pulled.away, 1.0);
        // The panel reaches about ten times the button's half diagonal from its axis.
        assert!(pulled.parent_reach_ratio > 5.0, "{pulled:?}");
    }

    #[test]
    fn a_lid_on_a_post_caps_it_and_lifting_it_goes_away() {
        // A 0.2-wide post 1 tall and a lid of its width on top.
        let s = Scene::of_convex_parts(
            &[
                TriMesh::cuboid(DVec3::ZERO, DVec3::new(0.2, 0.2, 1.0)),
                TriMesh::cuboid(DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.2, 0.2, 1.05)),
            ],
            1500,
        );
        let moving = s.points_of(&[1]);
        let touch = touching_samples(&s, 0, &moving, 0.005);
        let lifted = slide_side(&s, 0, &moving, &touch, DVec3::Z, (0.0, 0.05)).expect("side");
        assert_eq!(lifted.surround_share, 0.0);
        assert_eq!(lifted.away, 1.0);
        // The post is the lid's width.
        assert!(lifted.parent_reach_ratio <= 1.01, "{lifted:?}");
    }
}
