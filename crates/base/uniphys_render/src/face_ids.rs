use uniphys_geometry::{DVec3, TriMesh};

use crate::camera::{Camera, ViewTransform};
use crate::raster::{ScreenVertex, rasterise_triangle};

/// Which triangle is visible at each pixel, with its depth and normal.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceIdImage {
    /// Width in pixels.
    pub width_px: u32,
    /// Height in pixels.
    pub height_px: u32,
    /// Row-major; 0 = background, `i + 1` = triangle `i` of the mesh.
    pub face: Vec<u32>,
    /// View depth (along the viewing axis) in metres; `f32::INFINITY` on background.
    pub depth_m: Vec<f32>,
    /// Unit normal of the visible triangle turned toward the camera; `[0, 0, 0]` on background.
    pub normal_world: Vec<[f32; 3]>,
}

impl FaceIdImage {
    fn index(&self, x_px: u32, y_px: u32) -> Option<usize> {
        (x_px < self.width_px && y_px < self.height_px)
            .then(|| y_px as usize * self.width_px as usize + x_px as usize)
    }

    /// The 0-based triangle index seen at the pixel, `None` on background or outside the image.
    #[must_use]
    pub fn face_at(&self, x_px: u32, y_px: u32) -> Option<usize> {
        let id = *self.face.get(self.index(x_px, y_px)?)?;
        (id > 0).then(|| id as usize - 1)
    }

    /// View depth at the pixel in metres, `None` on background or outside the image.
    #[must_use]
    pub fn depth_at(&self, x_px: u32, y_px: u32) -> Option<f32> {
        let d = *self.depth_m.get(self.index(x_px, y_px)?)?;
        d.is_finite().then_some(d)
    }

    /// Number of pixels showing a triangle.
    #[must_use]
    pub fn covered_pixels(&self) -> usize {
        self.face.iter().filter(|&&f| f != 0).count()
    }
}

/// Z-buffered rasterisation of every triangle of `mesh` seen by `camera`; both sides of a
/// triangle are visible. Deterministic.
///
/// Rules: a pixel is covered when its centre is inside the triangle; a centre exactly on an edge
/// shared by two triangles belongs to exactly one of them (so closed surfaces have no cracks).
/// Depth is the view depth, interpolated perspective-correctly; the nearer triangle wins and on
/// equal depth the smaller triangle index wins. Triangles crossing the near plane
/// ([`Camera::near_m`]) are clipped against it; the part behind it is not drawn. Triangles with
/// an index that does not fit `u32::MAX - 1` are ignored.
#[must_use]
pub fn render_face_ids(mesh: &TriMesh, camera: &Camera) -> FaceIdImage {
    let mut image = FaceIdImage {
        width_px: 0,
        height_px: 0,
        face: Vec::new(),
        depth_m: Vec::new(),
        normal_world: Vec::new(),
    };
    render_face_ids_into(mesh, camera, &mut image);
    image
}

/// [`render_face_ids`] into an existing image, reusing its buffers (resized to the camera's
/// image): the same result without allocating when rendering many views of one size.
pub fn render_face_ids_into(mesh: &TriMesh, camera: &Camera, image: &mut FaceIdImage) {
    let width = camera.width_px as usize;
    let height = camera.height_px as usize;
    let pixel_count = width * height;
    let view = ViewTransform::new(camera);
    let view_positions: Vec<DVec3> = mesh
        .positions
        .iter()
        .map(|&p| view.view_from_world(p))
        .collect();
    let screen: Vec<ScreenVertex> = view_positions
        .iter()
        .map(|&p| ScreenVertex::project(&view, p))
        .collect();

    image.width_px = camera.width_px;
    image.height_px = camera.height_px;
    // The depth buffer holds the inverse view depth while rasterising (0 is background,
    // larger is nearer) and is turned into depth afterwards.
    reset(&mut image.depth_m, pixel_count, 0.0);
    reset(&mut image.face, pixel_count, 0);
    let mut target = crate::raster::Target {
        width_px: width,
        height_px: height,
        inv_depth: &mut image.depth_m,
        face: &mut image.face,
    };
    for (i, tri) in mesh.triangles.iter().enumerate() {
        let Some(id) = u32::try_from(i).ok().and_then(|i| i.checked_add(1)) else {
            break;
        };
        let [a, b, c] = tri.map(|v| v as usize);
        let (Some(&pa), Some(&pb), Some(&pc)) = (
            view_positions.get(a),
            view_positions.get(b),
            view_positions.get(c),
        ) else {
            continue;
        };
        let near = view.near_m;
        if pa.z >= near && pb.z >= near && pc.z >= near {
            rasterise_triangle(&mut target, [screen[a], screen[b], screen[c]], id);
        } else if pa.z >= near || pb.z >= near || pc.z >= near {
            let polygon = clip_near([pa, pb, pc], near);
            let projected: Vec<ScreenVertex> = polygon
                .iter()
                .map(|&p| ScreenVertex::project(&view, p))
                .collect();
            for k in 1..projected.len().saturating_sub(1) {
                rasterise_triangle(
                    &mut target,
                    [projected[0], projected[k], projected[k + 1]],
                    id,
                );
            }
        }
    }

    reset(&mut image.normal_world, pixel_count, [0.0; 3]);
    let mut cached: Option<(u32, [f32; 3])> = None;
    for ((&id, depth), normal) in image
        .face
        .iter()
        .zip(image.depth_m.iter_mut())
        .zip(image.normal_world.iter_mut())
    {
        if id == 0 {
            *depth = f32::INFINITY;
            continue;
        }
        *depth = 1.0 / *depth;
        *normal = match cached {
            Some((cached_id, n)) if cached_id == id => n,
            _ => {
                let n = facing_normal(mesh, id as usize - 1, camera.eye_m);
                cached = Some((id, n));
                n
            }
        };
    }
}

/// `buffer` with `len` copies of `value`, keeping its allocation.
fn reset<T: Copy>(buffer: &mut Vec<T>, len: usize, value: T) {
    buffer.clear();
    buffer.resize(len, value);
}

/// The unit normal of triangle `i` turned toward `eye_m`.
fn facing_normal(mesh: &TriMesh, i: usize, eye_m: DVec3) -> [f32; 3] {
    let [a, _, _] = mesh.corners(i);
    let n = mesh.scaled_normal(i).normalize_or_zero();
    let n = if n.dot(eye_m - a) < 0.0 { -n } else { n };
    [n.x as f32, n.y as f32, n.z as f32]
}

/// The part of a view-space triangle with depth `z >= near_m` (Sutherland-Hodgman against one
/// plane): a triangle or a quad, in order.
fn clip_near(corners: [DVec3; 3], near_m: f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(4);
    for k in 0..3 {
        let a = corners[k];
        let b = corners[(k + 1) % 3];
        let a_in = a.z >= near_m;
        let b_in = b.z >= near_m;
        if a_in {
            out.push(a);
        }
        if a_in != b_in {
            let t = (near_m - a.z) / (b.z - a.z);
            let mut p = a + (b - a) * t;
            p.z = near_m;
            out.push(p);
        }
    }
    out
}
