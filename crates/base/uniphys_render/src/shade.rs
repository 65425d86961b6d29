use uniphys_geometry::DVec3;

use crate::camera::{Camera, ViewTransform};
use crate::face_ids::FaceIdImage;
use crate::rgba::RgbaImage;

/// Share of a face's colour it keeps when facing away from the light.
pub const AMBIENT: f64 = 0.35;

/// Unit direction towards the light in the world frame: a head light from slightly above and
/// left of the camera, so faces of different orientation get different shades.
#[must_use]
pub fn light_direction(camera: &Camera) -> DVec3 {
    let view = ViewTransform::new(camera);
    (-view.forward + 0.45 * view.up - 0.3 * view.right).normalize()
}

/// Lambert shading factor in `[AMBIENT, 1]` of a surface with unit normal `normal`.
#[must_use]
pub fn lambert(normal: DVec3, light: DVec3) -> f64 {
    AMBIENT + (1.0 - AMBIENT) * normal.dot(light).max(0.0)
}

/// Lambert-shaded colour image: `face_rgba(face_index)` colours each visible face (0-based
/// triangle index, alpha kept); background transparent.
#[must_use]
pub fn shade(
    image: &FaceIdImage,
    camera: &Camera,
    face_rgba: &dyn Fn(usize) -> [u8; 4],
) -> RgbaImage {
    let light = light_direction(camera);
    let mut out = RgbaImage::new(image.width_px, image.height_px, [0; 4]);
    for (k, (&id, n)) in image.face.iter().zip(&image.normal_world).enumerate() {
        if id == 0 {
            continue;
        }
        let normal = DVec3::new(f64::from(n[0]), f64::from(n[1]), f64::from(n[2]));
        let f = lambert(normal, light);
        let c = face_rgba(id as usize - 1);
        let scale = |v: u8| (f64::from(v) * f).round().clamp(0.0, 255.0) as u8;
        if let Some(p) = out.pixels.get_mut(k) {
            *p = [scale(c[0]), scale(c[1]), scale(c[2]), c[3]];
        }
    }
    out
}
