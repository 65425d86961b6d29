//! The object rendered as two layers, the target part and the rest, composited so the rest
//! is translucent.

use uniphys_geometry::{Aabb, DVec3, TriMesh};

use super::PartScene;
use super::colours::{CONTEXT_GREY, DEFAULT_PART, WHITE};
use crate::camera::Camera;
use crate::face_ids::{FaceIdImage, render_face_ids};
use crate::rgba::{RgbaImage, over};
use crate::shade::{lambert, light_direction};

/// Opacity of the context parts in front of the target.
const CONTEXT_ALPHA_OVER_TARGET: f64 = 0.4;
/// Opacity of the context parts elsewhere.
const CONTEXT_ALPHA: f64 = 0.55;
/// Renders are made this many times larger in each direction and averaged down (anti-aliasing).
pub(crate) const SUPERSAMPLING: u32 = 2;

/// `camera` with an image [`SUPERSAMPLING`] times larger (same field of view).
fn supersampled(camera: &Camera) -> Camera {
    Camera {
        width_px: camera.width_px * SUPERSAMPLING,
        height_px: camera.height_px * SUPERSAMPLING,
        ..*camera
    }
}

/// The target part's mesh and colour and all other parts merged.
pub(crate) struct SplitScene {
    pub(crate) target: TriMesh,
    pub(crate) rest: TriMesh,
    pub(crate) target_rgba: [u8; 4],
}

impl SplitScene {
    pub(crate) fn new(scene: &PartScene<'_>, part: usize) -> Self {
        let target = scene.part_meshes.get(part).cloned().unwrap_or_default();
        let rest = TriMesh::merge(
            scene
                .part_meshes
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != part)
                .map(|(_, m)| m),
        );
        let target_rgba = scene.part_rgba.get(part).copied().unwrap_or(DEFAULT_PART);
        Self {
            target,
            rest,
            target_rgba: [target_rgba[0], target_rgba[1], target_rgba[2], 255],
        }
    }

    /// Bounds of the target part (of the whole object when the part is empty).
    pub(crate) fn target_bounds(&self) -> Aabb {
        if self.target.triangles.is_empty() {
            self.object_bounds()
        } else {
            self.target.bounds()
        }
    }

    /// Bounds of all parts.
    pub(crate) fn object_bounds(&self) -> Aabb {
        self.target.bounds().union(self.rest.bounds())
    }
}

/// Lambert-shaded colour of pixel `k` of `image`, or `None` on background.
fn shaded(image: &FaceIdImage, k: usize, light: DVec3, rgb: [u8; 3]) -> Option<[u8; 3]> {
    if image.face.get(k).copied().unwrap_or(0) == 0 {
        return None;
    }
    let n = image.normal_world.get(k)?;
    let f = lambert(
        DVec3::new(f64::from(n[0]), f64::from(n[1]), f64::from(n[2])),
        light,
    );
    Some(rgb.map(|c| (f64::from(c) * f).round().clamp(0.0, 255.0) as u8))
}

fn with_alpha(rgb: [u8; 3], alpha: f64) -> [u8; 4] {
    [rgb[0], rgb[1], rgb[2], (255.0 * alpha).round() as u8]
}

/// How the target part is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TargetStyle {
    /// Opaque in its colour; the other parts translucent grey over it.
    Opaque,
    /// Translucent in its colour (this opacity) over faint context.
    Translucent(f64),
}

/// The scene from `camera` on white (anti-aliased by [`SUPERSAMPLING`]): the target part in its
/// colour, the other parts light grey and translucent, so the target shows through parts in
/// front of it.
pub(crate) fn context_image(split: &SplitScene, camera: &Camera, style: TargetStyle) -> RgbaImage {
    let camera = &supersampled(camera);
    let target = render_face_ids(&split.target, camera);
    let rest = render_face_ids(&split.rest, camera);
    let light = light_direction(camera);
    let colour = [
        split.target_rgba[0],
        split.target_rgba[1],
        split.target_rgba[2],
    ];
    let mut out = RgbaImage::new(camera.width_px, camera.height_px, WHITE);
    for (k, px) in out.pixels.iter_mut().enumerate() {
        let t = shaded(&target, k, light, colour);
        let r = shaded(&rest, k, light, CONTEXT_GREY);
        match style {
            TargetStyle::Opaque => {
                if let Some(t) = t {
                    *px = [t[0], t[1], t[2], 255];
                }
                if let Some(r) = r {
                    let rest_in_front = rest.depth_m[k] < target.depth_m[k];
                    if t.is_none() {
                        *px = over(with_alpha(r, CONTEXT_ALPHA), *px);
                    } else if rest_in_front {
                        *px = over(with_alpha(r, CONTEXT_ALPHA_OVER_TARGET), *px);
                    }
                }
            }
            TargetStyle::Translucent(alpha) => {
                if let Some(r) = r {
                    *px = over(with_alpha(r, 0.5 * CONTEXT_ALPHA), *px);
                }
                if let Some(t) = t {
                    *px = over(with_alpha(t, alpha), *px);
                }
            }
        }
    }
    out.downsampled(SUPERSAMPLING)
}

/// The target part alone from `camera`, opaque in its colour on white.
pub(crate) fn alone_image(split: &SplitScene, camera: &Camera) -> RgbaImage {
    let camera = &supersampled(camera);
    let target = render_face_ids(&split.target, camera);
    let light = light_direction(camera);
    let colour = [
        split.target_rgba[0],
        split.target_rgba[1],
        split.target_rgba[2],
    ];
    let mut out = RgbaImage::new(camera.width_px, camera.height_px, WHITE);
    for (k, px) in out.pixels.iter_mut().enumerate() {
        if let Some(t) = shaded(&target, k, light, colour) {
            *px = [t[0], t[1], t[2], 255];
        }
    }
    out.downsampled(SUPERSAMPLING)
}
