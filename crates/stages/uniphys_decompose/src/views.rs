//! Multi-view renders of the merged mesh (reference §2): per view the visible face, depth and
//! normal of every pixel, and a shaded colour image, from cameras around the object.

use uniphys_geometry::{
    DMat3, DVec3, MeshAsset, TriMesh, linear_to_srgb8, srgb8_to_linear, texel_rgba8,
};
use uniphys_render::{Camera, FaceIdImage, RgbaImage, orbit_cameras, render_face_ids, shade};

use crate::{DecomposeError, DecomposeResult};

/// Largest accepted image side, pixels.
pub const MAX_RESOLUTION_PX: u32 = 4096;
/// Most views accepted.
pub const MAX_VIEW_COUNT: usize = 64;

/// How many views and how large.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ViewOptions {
    /// Number of cameras (default 8, the reference rig).
    pub count: usize,
    /// Width and height of every image in pixels (default 512).
    pub resolution_px: u32,
}

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            count: 8,
            resolution_px: 512,
        }
    }
}

/// The rendered views, index `k` of every vector belonging to view `k`.
#[derive(Debug, Clone)]
pub struct ViewSet {
    /// The cameras.
    pub cameras: Vec<Camera>,
    /// Face, depth and normal per pixel.
    pub face_ids: Vec<FaceIdImage>,
    /// Lambert-shaded colour images with a transparent background.
    pub colour: Vec<RgbaImage>,
}

/// Renders `options.count` views of `mesh` from [`orbit_cameras`] around its bounds, each face
/// coloured `face_rgba[face]`. Deterministic.
pub fn render_views(
    mesh: &TriMesh,
    face_rgba: &[[u8; 4]],
    options: &ViewOptions,
) -> DecomposeResult<ViewSet> {
    render_views_on(mesh, face_rgba, options, 1)
}

/// [`render_views`] on up to `threads` threads (same result).
pub(crate) fn render_views_on(
    mesh: &TriMesh,
    face_rgba: &[[u8; 4]],
    options: &ViewOptions,
    threads: usize,
) -> DecomposeResult<ViewSet> {
    let faces = mesh.triangle_count();
    if faces == 0 {
        return Err(DecomposeError::InvalidInput("the mesh has no faces".into()));
    }
    if face_rgba.len() != faces {
        return Err(DecomposeError::InvalidInput(format!(
            "{} face colours for {faces} faces",
            face_rgba.len()
        )));
    }
    if options.count == 0 || options.count > MAX_VIEW_COUNT {
        return Err(DecomposeError::InvalidOption(format!(
            "view count {} (1 to {MAX_VIEW_COUNT})",
            options.count
        )));
    }
    if options.resolution_px < 8 || options.resolution_px > MAX_RESOLUTION_PX {
        return Err(DecomposeError::InvalidOption(format!(
            "view resolution {} px (8 to {MAX_RESOLUTION_PX})",
            options.resolution_px
        )));
    }
    let side = options.resolution_px;
    let cameras = orbit_cameras(&mesh.bounds(), options.count, side, side);
    let colour_of = |face: usize| face_rgba.get(face).copied().unwrap_or([0, 0, 0, 0]);
    let rendered = map_views(cameras.len(), threads, &|k| {
        let image = render_face_ids(mesh, &cameras[k]);
        let colour = shade(&image, &cameras[k], &colour_of);
        Ok((image, colour))
    })?;
    let (face_ids, colour): (Vec<FaceIdImage>, Vec<RgbaImage>) = rendered.into_iter().unzip();
    Ok(ViewSet {
        cameras,
        face_ids,
        colour,
    })
}

/// `work(k)` for every view `k`, in view order, on up to `threads` scoped threads (view `k` on
/// thread `k % threads`). The first error in view order wins.
pub(crate) fn map_views<T: Send>(
    count: usize,
    threads: usize,
    work: &(dyn Fn(usize) -> DecomposeResult<T> + Sync),
) -> DecomposeResult<Vec<T>> {
    let threads = threads.clamp(1, count.max(1));
    if threads == 1 {
        return (0..count).map(work).collect();
    }
    let mut slots: Vec<Option<DecomposeResult<T>>> = (0..count).map(|_| None).collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                scope.spawn(move || {
                    (t..count)
                        .step_by(threads)
                        .map(|k| (k, work(k)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for (t, handle) in handles.into_iter().enumerate() {
            match handle.join() {
                Ok(results) => {
                    for (k, result) in results {
                        slots[k] = Some(result);
                    }
                }
                Err(_) => {
                    for k in (t..count).step_by(threads) {
                        slots[k] = Some(Err(DecomposeError::Segmentation {
                            view: k,
                            message: "the thread working on the view panicked".into(),
                        }));
                    }
                }
            }
        }
    });
    slots
        .into_iter()
        .enumerate()
        .map(|(k, slot)| {
            slot.unwrap_or_else(|| {
                Err(DecomposeError::Segmentation {
                    view: k,
                    message: "the view was not processed".into(),
                })
            })
        })
        .collect()
}

/// The pixel rays of a camera, precomputed: the point at pixel coordinates (x, y) and view
/// depth d is `eye + d * (origin + x * step_x + y * step_y)` (pixel centres at +0.5).
#[derive(Debug, Clone, Copy)]
pub(crate) struct PixelRays {
    eye_m: DVec3,
    origin: DVec3,
    step_x: DVec3,
    step_y: DVec3,
    /// Inverse of the matrix with columns `origin`, `step_x`, `step_y` (projection).
    inverse: DMat3,
    near_m: f64,
    /// Width of a pixel at a depth of 1 m, metres.
    pub(crate) footprint_per_m: f64,
}

impl PixelRays {
    /// The rays of `camera`, derived from [`Camera::unproject`].
    pub(crate) fn new(camera: &Camera) -> Self {
        let eye_m = camera.eye_m;
        let at = |x: f64, y: f64| camera.unproject(x, y, 1.0) - eye_m;
        let origin = at(0.0, 0.0);
        let step_x = at(1.0, 0.0) - origin;
        let step_y = at(0.0, 1.0) - origin;
        Self {
            eye_m,
            origin,
            step_x,
            step_y,
            inverse: DMat3::from_cols(origin, step_x, step_y).inverse(),
            near_m: camera.near_m(),
            footprint_per_m: step_x.length(),
        }
    }

    /// The visible point of pixel `(x, y)` at `depth_m`, relative to the eye.
    #[inline]
    pub(crate) fn point(&self, x: usize, y: usize, depth_m: f32) -> DVec3 {
        self.point_at(x as f64 + 0.5, y as f64 + 0.5, f64::from(depth_m))
    }

    /// The point at pixel coordinates `(x_px, y_px)` and view depth `depth_m`, relative to the
    /// eye.
    #[inline]
    pub(crate) fn point_at(&self, x_px: f64, y_px: f64, depth_m: f64) -> DVec3 {
        (self.origin + self.step_x * x_px + self.step_y * y_px) * depth_m
    }

    /// Pixel coordinates and view depth of a world point, `None` closer than the near plane
    /// (as [`Camera::project`]).
    #[inline]
    pub(crate) fn project(&self, point_world_m: DVec3) -> Option<(f64, f64, f64)> {
        let v = self.inverse * (point_world_m - self.eye_m);
        (v.x >= self.near_m && v.x.is_finite()).then(|| (v.y / v.x, v.z / v.x, v.x))
    }
}

/// Per-face colour of an asset's merged mesh (same face order as [`MeshAsset::merged`]): the
/// material's base colour x the base-colour texture at the face's UV centroid x the mean of the
/// face's vertex colours, multiplied in linear space and returned as sRGB bytes with alpha.
/// Faces without a material use white.
#[must_use]
pub fn face_colours(asset: &MeshAsset) -> Vec<[u8; 4]> {
    let mut out = Vec::with_capacity(asset.triangle_count());
    for part in &asset.parts {
        let mesh = &part.mesh;
        for (face, tri) in mesh.triangles.iter().enumerate() {
            let corners = tri.map(|v| v as usize);
            let mut linear = [1.0f32; 4];
            let mut multiply = |rgba: [f32; 4]| {
                for (l, x) in linear.iter_mut().zip(rgba) {
                    *l *= x;
                }
            };
            let material = mesh
                .face_materials
                .as_ref()
                .and_then(|m| m.get(face))
                .and_then(|&m| asset.materials.get(m as usize));
            if let Some(material) = material {
                multiply(material.base_color_rgba);
                let texture = material
                    .base_color_texture
                    .and_then(|t| asset.textures.get(t));
                if let (Some(texture), Some(uvs)) = (texture, &mesh.uvs) {
                    let centroid = [0, 1].map(|k| {
                        corners
                            .iter()
                            .map(|&v| uvs.get(v).map_or(0.0, |uv| uv[k]))
                            .sum::<f32>()
                            / 3.0
                    });
                    if let Some(texel) = texel_rgba8(texture, centroid) {
                        let [r, g, b, a] = texel;
                        multiply([
                            srgb8_to_linear(r),
                            srgb8_to_linear(g),
                            srgb8_to_linear(b),
                            f32::from(a) / 255.0,
                        ]);
                    }
                }
            }
            if let Some(colors) = &mesh.vertex_colors {
                multiply([0, 1, 2, 3].map(|k| {
                    corners
                        .iter()
                        .map(|&v| colors.get(v).map_or(1.0, |c| c[k]))
                        .sum::<f32>()
                        / 3.0
                }));
            }
            let [r, g, b, a] = linear;
            out.push([
                linear_to_srgb8(r),
                linear_to_srgb8(g),
                linear_to_srgb8(b),
                (a.clamp(0.0, 1.0) * 255.0).round() as u8,
            ]);
        }
    }
    out
}

/// Material index of every face of an asset's merged mesh (same order as
/// [`MeshAsset::merged`]); faces without one get `u32::MAX`.
#[must_use]
pub fn face_material_ids(asset: &MeshAsset) -> Vec<u32> {
    asset
        .parts
        .iter()
        .flat_map(|part| {
            let count = part.mesh.triangle_count();
            (0..count).map(move |face| {
                part.mesh
                    .face_materials
                    .as_ref()
                    .and_then(|m| m.get(face).copied())
                    .unwrap_or(u32::MAX)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::{DVec3, MeshPart, SurfaceMaterial, Texture};

    use super::*;

    #[test]
    fn face_colours_multiply_material_texture_and_vertex_colours() {
        // Part 0: material 0 (half-grey base colour) with a 2 x 1 texture, red left, blue right;
        // its faces' UV centroids fall on the left. Part 1: no material, white vertex colours
        // except one green-tinted vertex.
        let cube = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let n = cube.positions.len();
        let textured = cube
            .clone()
            .with_uvs(vec![[0.25, 0.5]; n])
            .and_then(|m| m.with_face_materials(vec![0; 12]));
        let tinted = cube.with_vertex_colors(
            (0..n)
                .map(|v| {
                    if v == 0 {
                        [0.0, 1.0, 0.0, 1.0]
                    } else {
                        [1.0; 4]
                    }
                })
                .collect(),
        );
        let (Ok(textured), Ok(tinted)) = (textured, tinted) else {
            panic!("valid attributes");
        };
        let asset = MeshAsset {
            parts: vec![
                MeshPart {
                    name: "a".into(),
                    mesh: textured,
                },
                MeshPart {
                    name: "b".into(),
                    mesh: tinted,
                },
            ],
            materials: vec![SurfaceMaterial {
                name: "grey".into(),
                base_color_rgba: [0.5, 0.5, 0.5, 1.0],
                base_color_texture: Some(0),
            }],
            textures: vec![Texture {
                name: "t".into(),
                width: 2,
                height: 1,
                rgba8: vec![255, 0, 0, 255, 0, 0, 255, 255],
            }],
            joints: vec![],
        };
        let colours = face_colours(&asset);
        assert_eq!(colours.len(), 24);
        // Linear 0.5 red is sRGB 188.
        assert_eq!(colours[0], [188, 0, 0, 255]);
        // Face 0 of the cube uses vertex 0: red and blue drop to 2/3 (sRGB 213), green stays.
        assert_eq!(colours[12], [213, 255, 213, 255]);
        // Face 2 (+z) does not touch vertex 0.
        assert_eq!(colours[14], [255, 255, 255, 255]);
        let ids = face_material_ids(&asset);
        assert_eq!((ids[0], ids[12]), (0, u32::MAX));
    }

    #[test]
    fn pixel_rays_project_and_unproject_like_the_camera() {
        let bounds = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.5, 0.3)).bounds();
        for camera in uniphys_render::orbit_cameras(&bounds, 8, 40, 30) {
            let rays = PixelRays::new(&camera);
            for point in [
                DVec3::ZERO,
                DVec3::new(1.0, 0.5, 0.3),
                DVec3::new(0.7, 0.1, 0.2),
            ] {
                let (Some(p), Some((x, y, depth))) = (camera.project(point), rays.project(point))
                else {
                    panic!("in front of the camera");
                };
                assert!((p.x_px - x).abs() < 1e-9 && (p.y_px - y).abs() < 1e-9);
                assert!((p.depth_m - depth).abs() < 1e-9);
                let back = camera.eye_m + rays.point_at(x, y, depth);
                assert!(back.distance(point) < 1e-9, "{back} != {point}");
            }
            // Behind the camera.
            let behind = camera.eye_m + (camera.eye_m - camera.target_m);
            assert!(rays.project(behind).is_none() && camera.project(behind).is_none());
        }
    }

    #[test]
    fn views_are_rendered_at_the_requested_size_and_invalid_options_refused() {
        let mesh = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let rgba = vec![[200, 100, 50, 255]; 12];
        let options = ViewOptions {
            count: 3,
            resolution_px: 32,
        };
        let Ok(views) = render_views(&mesh, &rgba, &options) else {
            panic!("renders");
        };
        assert_eq!(
            (
                views.cameras.len(),
                views.face_ids.len(),
                views.colour.len()
            ),
            (3, 3, 3)
        );
        for (ids, colour) in views.face_ids.iter().zip(&views.colour) {
            assert_eq!((ids.width_px, ids.height_px), (32, 32));
            assert!(ids.covered_pixels() > 32);
            // Colour is opaque exactly where a face is visible.
            for (face, px) in ids.face.iter().zip(&colour.pixels) {
                assert_eq!(*face > 0, px[3] > 0);
            }
        }
        let bad = ViewOptions {
            count: 0,
            ..options
        };
        assert!(matches!(
            render_views(&mesh, &rgba, &bad),
            Err(DecomposeError::InvalidOption(_))
        ));
        assert!(matches!(
            render_views(&mesh, &rgba[..5], &options),
            Err(DecomposeError::InvalidInput(_))
        ));
    }
}
