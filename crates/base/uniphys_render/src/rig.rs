use uniphys_geometry::{Aabb, DVec3};

use crate::camera::{Camera, DEFAULT_FOV_Y_RAD, ViewTransform};

/// Directions (before normalisation) of the reference's 8-view rig, in its order: view k looks
/// at the centre from `centre + direction_k * distance` (reference §2, Z up).
pub const REFERENCE_RIG_DIRECTIONS: [[f64; 3]; 8] = [
    [1.0, 1.0, 0.7],
    [-1.0, 1.0, 0.7],
    [1.0, 1.0, -0.7],
    [-1.0, 1.0, -0.7],
    [1.0, -1.0, 0.7],
    [-1.0, -1.0, 0.7],
    [1.0, -1.0, -0.7],
    [-1.0, -1.0, -0.7],
];

/// Fraction of the image half-size left free around a framed box.
const FRAME_MARGIN: f64 = 0.05;

/// `count` cameras looking at the centre of `bounds`, each far enough that the whole box is in
/// view (field of view [`DEFAULT_FOV_Y_RAD`], Z up).
///
/// `count == 8` is the reference rig ([`REFERENCE_RIG_DIRECTIONS`] normalised, in that order);
/// other counts use a Fibonacci spiral over the sphere (deterministic, evenly spread).
#[must_use]
pub fn orbit_cameras(bounds: &Aabb, count: usize, width_px: u32, height_px: u32) -> Vec<Camera> {
    orbit_directions(count)
        .into_iter()
        .map(|d| camera_from_direction(bounds, d, width_px, height_px))
        .collect()
}

/// Unit view directions (from the centre towards the eye) of [`orbit_cameras`].
#[must_use]
pub fn orbit_directions(count: usize) -> Vec<DVec3> {
    if count == REFERENCE_RIG_DIRECTIONS.len() {
        return REFERENCE_RIG_DIRECTIONS
            .iter()
            .map(|d| DVec3::from_array(*d).normalize())
            .collect();
    }
    uniphys_geometry::sphere_directions(count)
}

/// One camera looking at the centre of `bounds` from `direction_world` (from the centre towards
/// the eye; need not be unit), at the smallest distance at which all 8 corners of the box lie
/// inside the image with a 5 % margin. Field of view [`DEFAULT_FOV_Y_RAD`], Z up (Y up when
/// looking along Z). A zero direction is replaced by the rig's first direction; an empty or
/// point-like box by a 2 mm box around its centre (or the origin).
#[must_use]
pub fn camera_from_direction(
    bounds: &Aabb,
    direction_world: DVec3,
    width_px: u32,
    height_px: u32,
) -> Camera {
    let bounds = usable_bounds(bounds);
    let centre = bounds.center();
    let dir =
        direction_world.normalize_or(DVec3::from_array(REFERENCE_RIG_DIRECTIONS[0]).normalize());
    let up = if dir.cross(DVec3::Z).length_squared() < 1e-12 {
        DVec3::Y
    } else {
        DVec3::Z
    };
    // The camera frame does not depend on the distance: build it at unit distance.
    let probe = Camera::look_at(
        centre + dir,
        centre,
        up,
        DEFAULT_FOV_Y_RAD,
        width_px,
        height_px,
    );
    let view = ViewTransform::new(&probe);
    let tan_y = (0.5 * DEFAULT_FOV_Y_RAD).tan() * (1.0 - FRAME_MARGIN);
    let aspect = f64::from(width_px.max(1)) / f64::from(height_px.max(1));
    let tan_x = tan_y * aspect;
    // A corner at offset (x, y, z) from the centre (camera frame, z along the view) is inside
    // when |x| <= tan_x (d + z) and |y| <= tan_y (d + z); d is the eye-to-centre distance.
    let mut distance = 0.0_f64;
    for corner in corners(&bounds) {
        let o = corner - centre;
        let x = o.dot(view.right).abs();
        let y = o.dot(view.up).abs();
        let z = o.dot(view.forward);
        distance = distance.max(x / tan_x - z).max(y / tan_y - z);
        // Keep every corner well in front of the near plane.
        distance = distance.max(1.05 * o.length());
    }
    Camera::look_at(
        centre + dir * distance,
        centre,
        up,
        DEFAULT_FOV_Y_RAD,
        width_px,
        height_px,
    )
}

fn usable_bounds(bounds: &Aabb) -> Aabb {
    const HALF_M: f64 = 1e-3;
    if bounds.is_empty() || !bounds.min.is_finite() || !bounds.max.is_finite() {
        return Aabb {
            min: DVec3::splat(-HALF_M),
            max: DVec3::splat(HALF_M),
        };
    }
    if bounds.diagonal() < 2.0 * HALF_M {
        let c = bounds.center();
        return Aabb {
            min: c - DVec3::splat(HALF_M),
            max: c + DVec3::splat(HALF_M),
        };
    }
    *bounds
}

/// The 8 corners of a box.
pub(crate) fn corners(b: &Aabb) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}
