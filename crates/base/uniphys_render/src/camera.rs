use uniphys_geometry::DVec3;

/// Vertical field of view chosen by the functions that pick one: 40 degrees.
pub const DEFAULT_FOV_Y_RAD: f64 = 40.0 * std::f64::consts::PI / 180.0;

/// Distance of the near clipping plane as a fraction of the eye-to-target distance.
pub const NEAR_FRACTION: f64 = 1e-3;

/// A pinhole camera with a symmetric vertical field of view and square pixels.
///
/// The camera looks from `eye_m` at `target_m`; `up` fixes the roll (it need not be unit or
/// orthogonal to the view direction). Image x grows to the right, y downwards.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position in the world frame, metres.
    pub eye_m: DVec3,
    /// Point the camera looks at, world frame, metres.
    pub target_m: DVec3,
    /// World direction that appears upwards in the image.
    pub up: DVec3,
    /// Full vertical field of view, radians.
    pub fov_y_rad: f64,
    /// Image width in pixels.
    pub width_px: u32,
    /// Image height in pixels.
    pub height_px: u32,
}

/// A world point projected into a camera's image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projected {
    /// Horizontal pixel coordinate (pixel `i` spans `[i, i + 1)`, its centre is `i + 0.5`).
    pub x_px: f64,
    /// Vertical pixel coordinate, downwards.
    pub y_px: f64,
    /// Depth along the viewing axis, metres (not the Euclidean distance).
    pub depth_m: f64,
}

impl Camera {
    /// A camera at `eye_m` looking at `target_m` with `up` upwards in the image.
    #[must_use]
    pub fn look_at(
        eye_m: DVec3,
        target_m: DVec3,
        up: DVec3,
        fov_y_rad: f64,
        width_px: u32,
        height_px: u32,
    ) -> Camera {
        Camera {
            eye_m,
            target_m,
            up,
            fov_y_rad,
            width_px,
            height_px,
        }
    }

    /// Pixel coordinates (x right, y down, pixel centres at +0.5) and view depth in metres of a
    /// world point; `None` behind the camera or closer than the near plane ([`Camera::near_m`]).
    #[must_use]
    pub fn project(&self, point_world_m: DVec3) -> Option<Projected> {
        let view = ViewTransform::new(self);
        let p = view.view_from_world(point_world_m);
        if p.z < view.near_m {
            return None;
        }
        let (x_px, y_px) = view.screen(p);
        Some(Projected {
            x_px,
            y_px,
            depth_m: p.z,
        })
    }

    /// The world point seen at pixel coordinates (`x_px`, `y_px`) at view depth `depth_m`.
    #[must_use]
    pub fn unproject(&self, x_px: f64, y_px: f64, depth_m: f64) -> DVec3 {
        let view = ViewTransform::new(self);
        let x = (x_px - view.centre_x_px) / view.focal_px * depth_m;
        let y = (view.centre_y_px - y_px) / view.focal_px * depth_m;
        view.eye_m + view.right * x + view.up * y + view.forward * depth_m
    }

    /// Unit viewing direction (from the eye towards the target).
    #[must_use]
    pub fn forward(&self) -> DVec3 {
        ViewTransform::new(self).forward
    }

    /// Distance of the near clipping plane: [`NEAR_FRACTION`] of the eye-to-target distance.
    #[must_use]
    pub fn near_m(&self) -> f64 {
        near_plane_m(self.eye_m, self.target_m)
    }
}

fn near_plane_m(eye_m: DVec3, target_m: DVec3) -> f64 {
    (NEAR_FRACTION * eye_m.distance(target_m)).max(1e-9)
}

/// The camera's orthonormal frame and intrinsics, computed once per render.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ViewTransform {
    pub(crate) eye_m: DVec3,
    /// Image right in the world frame.
    pub(crate) right: DVec3,
    /// Image up in the world frame.
    pub(crate) up: DVec3,
    /// Viewing direction in the world frame.
    pub(crate) forward: DVec3,
    /// Focal length in pixels (square pixels).
    pub(crate) focal_px: f64,
    pub(crate) centre_x_px: f64,
    pub(crate) centre_y_px: f64,
    pub(crate) near_m: f64,
}

impl ViewTransform {
    pub(crate) fn new(camera: &Camera) -> Self {
        let forward = (camera.target_m - camera.eye_m).normalize_or(DVec3::NEG_Z);
        // Fall back to the world axis least parallel to the view when `up` is unusable.
        let mut right = forward.cross(camera.up);
        if right.length_squared() < 1e-18 * camera.up.length_squared().max(1e-300)
            || !right.is_finite()
        {
            let a = forward.abs();
            let fallback = if a.z <= a.x && a.z <= a.y {
                DVec3::Z
            } else if a.y <= a.x {
                DVec3::Y
            } else {
                DVec3::X
            };
            right = forward.cross(fallback);
        }
        let right = right.normalize_or(DVec3::X);
        let up = right.cross(forward);
        let half = (0.5 * camera.fov_y_rad).clamp(1e-6, 0.5 * std::f64::consts::PI - 1e-6);
        let height = f64::from(camera.height_px.max(1));
        Self {
            eye_m: camera.eye_m,
            right,
            up,
            forward,
            focal_px: 0.5 * height / half.tan(),
            centre_x_px: 0.5 * f64::from(camera.width_px),
            centre_y_px: 0.5 * f64::from(camera.height_px),
            near_m: near_plane_m(camera.eye_m, camera.target_m),
        }
    }

    /// Camera-frame coordinates: x right, y up, z = depth along the view.
    #[inline]
    pub(crate) fn view_from_world(&self, p: DVec3) -> DVec3 {
        let d = p - self.eye_m;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.forward))
    }

    /// Pixel coordinates of a camera-frame point in front of the camera.
    #[inline]
    pub(crate) fn screen(&self, p_view: DVec3) -> (f64, f64) {
        let inv_z = 1.0 / p_view.z;
        (
            self.centre_x_px + self.focal_px * p_view.x * inv_z,
            self.centre_y_px - self.focal_px * p_view.y * inv_z,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera_on_x_axis() -> Camera {
        Camera::look_at(
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::ZERO,
            DVec3::Z,
            DEFAULT_FOV_Y_RAD,
            200,
            100,
        )
    }

    #[test]
    fn target_projects_to_the_image_centre_at_its_distance() {
        let cam = camera_on_x_axis();
        let p = cam.project(DVec3::ZERO).expect("in front");
        assert!((p.x_px - 100.0).abs() < 1e-12 && (p.y_px - 50.0).abs() < 1e-12);
        assert!((p.depth_m - 5.0).abs() < 1e-12);
    }

    #[test]
    fn the_top_edge_of_the_field_of_view_maps_to_row_zero_and_right_is_right() {
        let cam = camera_on_x_axis();
        let half = 0.5 * DEFAULT_FOV_Y_RAD;
        // Looking along -X with Z up, image right is world +Y.
        let top = cam
            .project(DVec3::new(0.0, 0.0, 5.0 * half.tan()))
            .expect("visible");
        assert!(top.y_px.abs() < 1e-9, "{top:?}");
        let right = cam.project(DVec3::new(0.0, 1.0, 0.0)).expect("visible");
        assert!(right.x_px > 100.0 && (right.y_px - 50.0).abs() < 1e-9);
        // Square pixels: one metre sideways moves as many pixels as one metre up.
        let up = cam.project(DVec3::new(0.0, 0.0, 1.0)).expect("visible");
        assert!(((right.x_px - 100.0) - (50.0 - up.y_px)).abs() < 1e-9);
    }

    #[test]
    fn points_behind_the_eye_do_not_project_and_unproject_inverts_project() {
        let cam = camera_on_x_axis();
        assert!(cam.project(DVec3::new(6.0, 0.0, 0.0)).is_none());
        let q = DVec3::new(0.3, -0.7, 0.4);
        let p = cam.project(q).expect("visible");
        let back = cam.unproject(p.x_px, p.y_px, p.depth_m);
        assert!(back.distance(q) < 1e-12, "{back}");
    }

    #[test]
    fn an_up_vector_parallel_to_the_view_still_gives_a_frame() {
        let cam = Camera::look_at(
            DVec3::new(0.0, 0.0, 3.0),
            DVec3::ZERO,
            DVec3::Z,
            1.0,
            64,
            64,
        );
        let p = cam.project(DVec3::ZERO).expect("in front");
        assert!((p.x_px - 32.0).abs() < 1e-12 && (p.y_px - 32.0).abs() < 1e-12);
        assert!(cam.project(DVec3::new(0.1, 0.2, 0.0)).is_some());
    }
}
