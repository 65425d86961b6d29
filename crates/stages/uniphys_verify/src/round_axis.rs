//! A part round about a line, and whether a hand would press it or turn it (reference:
//! real-articulated-objects.md, "Spin" and "Push"). The grounder asks it of a part nobody named;
//! the correction of a round part turned part-way asks it of the line it was turned about, so
//! the two agree on which round parts are buttons.
//!
//! Roundness is judged on the part's outline: its outer samples turned about the line by a few
//! angles that map no rectangle or square onto itself, and the share of them that land back on
//! the part's own surface. A small round part is a button when a hand has nothing to turn it by
//! (it is squat, and smooth all round: no ridge, pointer or knurl) and it sits on a face of its
//! parent (the face lies beside it all round, as around a button on a panel, rather than only
//! under it, as under a cap on a neck or a wheel on an axle).

use uniphys_geometry::{Aabb, DQuat, DVec3, projection_range};

use crate::scene::Scene;

/// Turns at which the part is compared with itself, radians (30, 75 and 130 degrees): no
/// rectangle or square maps onto itself at any of them, a round part does at all.
const TURNS_RAD: [f64; 3] = [
    std::f64::consts::FRAC_PI_6,
    5.0 * std::f64::consts::PI / 12.0,
    13.0 * std::f64::consts::PI / 18.0,
];
/// A turned sample is back on the part when it lies within this fraction of the part's box
/// diagonal of the part's own surface.
pub const ON_SURFACE_FRACTION: f64 = 0.02;
/// Samples at least this share of the farthest sample's distance from the axis are judged.
const OUTER_RADIUS_FRACTION: f64 = 0.5;
/// A part whose box diagonal is under this fraction of its parent's is small: a button, a knob.
pub const SMALL_PART_FRACTION: f64 = 0.2;
/// A round small part is turned when a hand can hold it: it stands this tall along its axis, as
/// a share of its width, to be pinched by its sides (a stub knob) ...
const PINCH_RATIO: f64 = 0.6;
/// ... or its outline is round only up to a grip (a ridge, a pointer, a knurl): under this share
/// of its outline maps onto itself when turned. Smooth all round and squat, it gives the fingers
/// nothing to turn it by: a button.
const SMOOTH_KEPT_FRACTION: f64 = 0.95;
/// A push travels this share of the part's depth along its axis ...
const PUSH_TRAVEL_FRACTION: f64 = 0.5;
/// ... unless its depth is under this share of its width: it is drawn as a single surface (no
/// thickness) ...
const FLAT_DEPTH_FRACTION: f64 = 0.01;
/// ... and is pushed this share of its width (a few millimetres for a finger-sized button).
const FLAT_STROKE_FRACTION: f64 = 0.1;
/// Directions around a round part's axis in which its parent's face is looked for ...
const FACE_DIRECTIONS: usize = 8;
/// ... and in how many of them the face must lie beside the part for it to sit on that face (a
/// button on a panel, possibly near its edge), rather than on the end of a neck it caps or an
/// axle it rolls on (the parent beside it in a few directions at most).
const FACE_DIRECTIONS_MIN: usize = 6;
/// Distances from the axis, in the part's widths, at which the face is looked for: from just
/// past its rim to half a width beyond it.
const FACE_REACH_WIDTHS: [f64; 3] = [0.7, 0.85, 1.0];
/// The face is there when the parent's surface lies within this share of the part's width of a
/// probe (probes are this far apart along the axis, over the part's length and as far past it).
const FACE_TOLERANCE_WIDTHS: f64 = 0.1;

/// A line a part is (nearly) round about, and the part's shape about it.
#[derive(Debug, Clone, Copy)]
pub struct RoundAxis {
    /// Unit axis, object frame.
    pub axis: DVec3,
    /// A point on it: the middle of the part's extent across and along the axis when the line
    /// was found from the part itself, else the point the line was given through; object frame.
    pub centre: DVec3,
    /// The smallest share of turned outer samples back on the part over the test turns.
    pub kept_fraction: f64,
    /// The part's largest extent across the axis, metres.
    pub width_m: f64,
    /// The part's extent along the axis over [`Self::width_m`]: a squat part (a button, a dial)
    /// is low, a stub (a knob to pinch, a bottle) high.
    pub length_over_width: f64,
}

impl RoundAxis {
    /// The shape of `part` (sampled at `points`, box diagonal `part_diagonal_m`) about the line
    /// along unit `axis` through `through`.
    #[must_use]
    pub fn about_line(
        scene: &Scene,
        part: usize,
        points: &[DVec3],
        part_diagonal_m: f64,
        axis: DVec3,
        through: DVec3,
    ) -> Self {
        let tolerance = ON_SURFACE_FRACTION * part_diagonal_m;
        let (u, v) = across(axis);
        let extent = |d: DVec3| {
            let (lo, hi) = projection_range(points, d);
            (hi - lo).max(0.0)
        };
        let width_m = extent(u).max(extent(v));
        Self {
            axis,
            centre: through,
            kept_fraction: kept_about_line(scene, part, points, axis, through, tolerance),
            width_m,
            length_over_width: extent(axis) / width_m.max(1e-12),
        }
    }

    /// Whether a hand would press this part rather than turn it: it is small (its box diagonal
    /// `part_diagonal_m` under [`SMALL_PART_FRACTION`] of its `parent`'s), squat and smooth all
    /// round, and sits on a face of its parent. A round knob, a cap or a wheel is turned.
    #[must_use]
    pub fn pressed(
        &self,
        scene: &Scene,
        parent: usize,
        points: &[DVec3],
        part_diagonal_m: f64,
    ) -> bool {
        let parent_diagonal_m = Aabb::from_points(&scene.points_of(&[parent])).diagonal();
        part_diagonal_m < SMALL_PART_FRACTION * parent_diagonal_m
            && self.pressed_not_turned(scene, parent, points)
    }

    /// Whether a small part round about this line is a button rather than a knob, a cap or a
    /// wheel: a hand cannot turn it (it is smooth all round and squat) and it sits on a face of
    /// its `parent`.
    fn pressed_not_turned(&self, scene: &Scene, parent: usize, points: &[DVec3]) -> bool {
        let graspable =
            self.length_over_width >= PINCH_RATIO || self.kept_fraction < SMOOTH_KEPT_FRACTION;
        !graspable && self.face_directions(scene, parent, points) >= FACE_DIRECTIONS_MIN
    }

    /// In how many of [`FACE_DIRECTIONS`] directions around the axis the parent's surface lies
    /// beside the part, at its own height along the axis (or within the tolerance past either
    /// end).
    fn face_directions(&self, scene: &Scene, parent: usize, points: &[DVec3]) -> usize {
        let (lo, hi) = projection_range(points, self.axis);
        let (u, v) = across(self.axis);
        let width = self.width_m;
        let tolerance = FACE_TOLERANCE_WIDTHS * width;
        if tolerance <= 0.0 {
            return 0;
        }
        let levels = ((hi - lo) / tolerance).ceil() as usize + 2;
        let on_axis = self.centre - self.axis * self.centre.dot(self.axis);
        (0..FACE_DIRECTIONS)
            .filter(|&k| {
                let angle = k as f64 * std::f64::consts::TAU / FACE_DIRECTIONS as f64;
                let out = u * angle.cos() + v * angle.sin();
                FACE_REACH_WIDTHS.iter().any(|reach| {
                    (0..=levels).any(|level| {
                        let height = lo - tolerance + level as f64 * tolerance;
                        let probe = on_axis + self.axis * height + out * (reach * width);
                        scene.distance_to_surface_m(parent, probe) <= tolerance
                    })
                })
            })
            .count()
    }
}

/// How far a small part of `depth_m` along its push and `width_m` across it is pushed: half its
/// depth, or a tenth of its width when it is drawn as a single surface and has no depth to read
/// its stroke from.
#[must_use]
pub fn push_travel_m(depth_m: f64, width_m: f64) -> f64 {
    if depth_m < FLAT_DEPTH_FRACTION * width_m {
        FLAT_STROKE_FRACTION * width_m
    } else {
        PUSH_TRAVEL_FRACTION * depth_m
    }
}

/// Two unit vectors completing `axis` to an orthonormal frame.
#[must_use]
pub fn across(axis: DVec3) -> (DVec3, DVec3) {
    let u = axis.any_orthonormal_vector();
    (u, axis.cross(u))
}

/// The centre of the points' box in the frame of `axis`.
#[must_use]
pub fn centre_about(points: &[DVec3], axis: DVec3) -> DVec3 {
    let (u, v) = across(axis);
    [axis, u, v]
        .iter()
        .map(|d| {
            let (lo, hi) = projection_range(points, *d);
            *d * (0.5 * (lo + hi))
        })
        .sum()
}

/// The smallest share of the outer `points` of `part` (at least half of the
/// farthest one's distance from the line along `axis` through `centre`) that land back within
/// `tolerance_m` of the part's surface over the test turns about that line. Only the outer
/// samples are judged: a turn barely moves those near the axis, and on a flat part (a door, a
/// lid) the faces' samples stay on the faces whatever its outline; the outline is what a turn
/// tests.
#[must_use]
pub fn kept_about_line(
    scene: &Scene,
    part: usize,
    points: &[DVec3],
    axis: DVec3,
    centre: DVec3,
    tolerance_m: f64,
) -> f64 {
    let radius = |p: &DVec3| (*p - centre).reject_from_normalized(axis).length();
    let farthest = points.iter().map(radius).fold(0.0, f64::max);
    let outer: Vec<DVec3> = points
        .iter()
        .filter(|p| radius(p) >= OUTER_RADIUS_FRACTION * farthest)
        .copied()
        .collect();
    TURNS_RAD
        .iter()
        .map(|&angle| {
            let turn = DQuat::from_axis_angle(axis, angle);
            let on = outer
                .iter()
                .filter(|p| {
                    let turned = centre + turn * (**p - centre);
                    scene.distance_to_surface_m(part, turned) <= tolerance_m
                })
                .count();
            on as f64 / outer.len().max(1) as f64
        })
        .fold(1.0, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_button_is_pushed_half_its_depth_and_one_without_thickness_a_tenth_of_its_width() {
        assert!((push_travel_m(0.008, 0.05) - 0.004).abs() < 1e-12);
        assert!((push_travel_m(0.0, 0.05) - 0.005).abs() < 1e-12);
    }
}
