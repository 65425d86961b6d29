use glam::DVec3;

use crate::color::{linear_to_srgb8, srgb8_to_linear, texel_rgb8};
use crate::{SplitMix64, SurfaceMaterial, Texture, TriMesh};

/// Points sampled uniformly over a mesh surface, with their face normals, colours and faces.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceSamples {
    /// Sample positions, metres.
    pub points: Vec<DVec3>,
    /// Unit normal of the face each sample lies on.
    pub normals: Vec<DVec3>,
    /// Surface colour at each sample, 8-bit sRGB.
    pub colors_rgb8: Vec<[u8; 3]>,
    /// Index of the triangle each sample lies on.
    pub faces: Vec<u32>,
}

/// Picks triangles with probability proportional to their area (cumulative areas plus binary
/// search) and uniform points inside them.
pub(crate) struct AreaSampler {
    cumulative: Vec<f64>,
    last_positive: usize,
}

impl AreaSampler {
    /// `None` if the mesh has no area (or a non-finite one).
    pub fn new(mesh: &TriMesh) -> Option<Self> {
        let mut total = 0.0;
        let mut last_positive = None;
        let cumulative = (0..mesh.triangle_count())
            .map(|i| {
                let area = mesh.face_area(i);
                if area > 0.0 {
                    last_positive = Some(i);
                }
                total += area;
                total
            })
            .collect();
        (total > 0.0 && total.is_finite()).then_some(Self {
            cumulative,
            last_positive: last_positive?,
        })
    }

    /// A triangle index (never one of zero area) and barycentric weights of a uniform point.
    pub fn sample(&self, rng: &mut SplitMix64) -> (usize, [f64; 3]) {
        let total = self.cumulative.last().copied().unwrap_or(0.0);
        let r = rng.next_f64() * total;
        let face = self.cumulative.partition_point(|&c| c <= r);
        let face = if face < self.cumulative.len() {
            face
        } else {
            self.last_positive
        };
        let (mut u, mut v) = (rng.next_f64(), rng.next_f64());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        (face, [1.0 - u - v, u, v])
    }
}

fn interpolate(mesh: &TriMesh, face: usize, w: [f64; 3]) -> DVec3 {
    let [a, b, c] = mesh.corners(face);
    a * w[0] + b * w[1] + c * w[2]
}

/// `count` points uniformly distributed over the surface of `mesh` (area-weighted triangle
/// choice, uniform barycentric point), with face normals and colours. Deterministic for a
/// given `seed`; a mesh without area gives no samples.
///
/// The colour follows glTF: the product, in linear space, of the face material's base colour
/// factor, its base colour texture at the interpolated UV (nearest pixel, repeating, v down)
/// and the interpolated vertex colour, each factor only if present; white if none is. So a
/// textured material gives the texel, an untextured one its base colour, a mesh without
/// materials its vertex colours.
#[must_use]
pub fn sample_surface(
    mesh: &TriMesh,
    materials: &[SurfaceMaterial],
    textures: &[Texture],
    count: usize,
    seed: u64,
) -> SurfaceSamples {
    let Some(sampler) = AreaSampler::new(mesh) else {
        return SurfaceSamples::default();
    };
    let mut rng = SplitMix64::new(seed);
    let mut out = SurfaceSamples {
        points: Vec::with_capacity(count),
        normals: Vec::with_capacity(count),
        colors_rgb8: Vec::with_capacity(count),
        faces: Vec::with_capacity(count),
    };
    for _ in 0..count {
        let (face, w) = sampler.sample(&mut rng);
        out.points.push(interpolate(mesh, face, w));
        out.normals.push(mesh.face_normal(face));
        out.colors_rgb8
            .push(surface_color(mesh, materials, textures, face, w));
        out.faces.push(u32::try_from(face).unwrap_or(u32::MAX));
    }
    out
}

/// `count` points uniformly distributed over the surface, the same points that
/// [`sample_surface`] gives for the same seed.
#[must_use]
pub fn sample_points(mesh: &TriMesh, count: usize, seed: u64) -> Vec<DVec3> {
    let Some(sampler) = AreaSampler::new(mesh) else {
        return Vec::new();
    };
    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let (face, w) = sampler.sample(&mut rng);
            interpolate(mesh, face, w)
        })
        .collect()
}

fn surface_color(
    mesh: &TriMesh,
    materials: &[SurfaceMaterial],
    textures: &[Texture],
    face: usize,
    w: [f64; 3],
) -> [u8; 3] {
    let [a, b, c] = mesh.triangles[face].map(|v| v as usize);
    let mut linear = [1.0f32; 3];
    let mut multiply = |rgb: [f32; 3]| {
        for (l, x) in linear.iter_mut().zip(rgb) {
            *l *= x;
        }
    };
    let material = mesh
        .face_materials
        .as_ref()
        .and_then(|m| materials.get(m[face] as usize));
    if let Some(material) = material {
        let [r, g, b_, _] = material.base_color_rgba;
        multiply([r, g, b_]);
        let texture = material.base_color_texture.and_then(|t| textures.get(t));
        if let (Some(texture), Some(uvs)) = (texture, &mesh.uvs) {
            let uv = [0, 1].map(|k| {
                let value = f64::from(uvs[a][k]) * w[0]
                    + f64::from(uvs[b][k]) * w[1]
                    + f64::from(uvs[c][k]) * w[2];
                value as f32
            });
            if let Some(texel) = texel_rgb8(texture, uv) {
                multiply(texel.map(srgb8_to_linear));
            }
        }
    }
    if let Some(colors) = &mesh.vertex_colors {
        multiply([0, 1, 2].map(|k| {
            let value = f64::from(colors[a][k]) * w[0]
                + f64::from(colors[b][k]) * w[1]
                + f64::from(colors[c][k]) * w[2];
            value as f32
        }));
    }
    linear.map(linear_to_srgb8)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_shapes::unit_box;

    fn quad() -> TriMesh {
        // The unit square in the z = 0 plane, counter-clockwise seen from +z.
        TriMesh::new(
            vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    }

    fn material(rgba: [f32; 4], texture: Option<usize>) -> SurfaceMaterial {
        SurfaceMaterial {
            name: "m".to_owned(),
            base_color_rgba: rgba,
            base_color_texture: texture,
        }
    }

    #[test]
    fn box_samples_lie_on_their_faces_with_unit_normals_and_area_weights() {
        let size = DVec3::new(1.0, 2.0, 3.0);
        let mesh = unit_box(DVec3::ZERO, size);
        let s = sample_surface(&mesh, &[], &[], 20_000, 3);
        assert_eq!(s.points.len(), 20_000);
        assert_eq!(s.normals.len(), 20_000);
        assert_eq!(s.colors_rgb8.len(), 20_000);
        assert_eq!(s.faces.len(), 20_000);
        let mut x_faces = 0;
        for ((p, n), &f) in s.points.iter().zip(&s.normals).zip(&s.faces) {
            assert!((n.length() - 1.0).abs() < 1e-12);
            assert_eq!(*n, mesh.face_normal(f as usize));
            // On the face plane: the coordinate along the normal is 0 or the size.
            let axis = n.abs().max_position();
            let expected = if n[axis] > 0.0 { size[axis] } else { 0.0 };
            assert!((p[axis] - expected).abs() < 1e-12, "{p} with normal {n}");
            assert!(p.cmpge(DVec3::splat(-1e-12)).all() && p.cmple(size + 1e-12).all());
            x_faces += usize::from(axis == 0);
        }
        // The two x faces hold 2 * 6 of the 22 m^2: 0.545 of the samples (std 0.004).
        let fraction = x_faces as f64 / 20_000.0;
        assert!((fraction - 12.0 / 22.0).abs() < 0.02, "{fraction}");
        assert!(s.colors_rgb8.iter().all(|&c| c == [255, 255, 255]));
    }

    #[test]
    fn same_seed_gives_the_same_samples_and_another_seed_does_not() {
        let mesh = unit_box(DVec3::ZERO, DVec3::ONE);
        let a = sample_surface(&mesh, &[], &[], 100, 9);
        assert_eq!(a, sample_surface(&mesh, &[], &[], 100, 9));
        assert_ne!(a.points, sample_surface(&mesh, &[], &[], 100, 10).points);
        assert_eq!(sample_points(&mesh, 100, 9), a.points);
    }

    #[test]
    fn zero_area_mesh_gives_no_samples() {
        let line =
            TriMesh::new(vec![DVec3::ZERO, DVec3::X, 2.0 * DVec3::X], vec![[0, 1, 2]]).unwrap();
        assert_eq!(
            sample_surface(&line, &[], &[], 10, 0),
            SurfaceSamples::default()
        );
        assert!(sample_points(&TriMesh::default(), 10, 0).is_empty());
    }

    #[test]
    fn zero_area_faces_are_never_chosen() {
        let mut mesh = quad();
        mesh.positions.push(DVec3::new(5.0, 5.0, 5.0));
        mesh.triangles.insert(0, [4, 4, 4]);
        mesh.triangles.push([4, 4, 4]);
        let s = sample_surface(&mesh, &[], &[], 1000, 1);
        assert!(s.faces.iter().all(|&f| f == 1 || f == 2));
    }

    #[test]
    fn texture_colour_is_the_texel_under_the_interpolated_uv() {
        // 2 x 2 texture, rows top to bottom: red green / blue white. UV (x, 1 - y) maps the
        // image upright onto the square, so the top-left quadrant (x < .5, y > .5) is red.
        let texture = Texture {
            name: "t".to_owned(),
            width: 2,
            height: 2,
            rgba8: vec![
                255, 0, 0, 255, 0, 255, 0, 255, //
                0, 0, 255, 255, 255, 255, 255, 255,
            ],
        };
        let mesh = quad()
            .with_uvs(vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
            .unwrap()
            .with_face_materials(vec![0, 0])
            .unwrap();
        let s = sample_surface(&mesh, &[material([1.0; 4], Some(0))], &[texture], 400, 5);
        let mut checked = 0;
        for (p, c) in s.points.iter().zip(&s.colors_rgb8) {
            if (p.x - 0.5).abs() < 1e-6 || (p.y - 0.5).abs() < 1e-6 {
                continue;
            }
            let expected = match (p.x < 0.5, p.y > 0.5) {
                (true, true) => [255, 0, 0],
                (false, true) => [0, 255, 0],
                (true, false) => [0, 0, 255],
                (false, false) => [255, 255, 255],
            };
            assert_eq!(*c, expected, "at {p}");
            checked += 1;
        }
        assert!(checked > 390);
    }

    #[test]
    fn colour_falls_back_to_base_colour_then_vertex_colour_then_white() {
        // Linear 0.5 encodes to sRGB 188.
        let with_material = quad().with_face_materials(vec![0, 0]).unwrap();
        let base = sample_surface(
            &with_material,
            &[material([0.5, 0.0, 1.0, 1.0], None)],
            &[],
            5,
            0,
        );
        assert!(base.colors_rgb8.iter().all(|&c| c == [188, 0, 255]));
        // A texture index without UVs on the mesh also falls back to the base colour.
        let missing_uvs = sample_surface(
            &with_material,
            &[material([0.5, 0.0, 1.0, 1.0], Some(0))],
            &[],
            5,
            0,
        );
        assert_eq!(missing_uvs.colors_rgb8, base.colors_rgb8);
        let painted = quad()
            .with_vertex_colors(vec![[0.5, 1.0, 0.0, 1.0]; 4])
            .unwrap();
        let vertex = sample_surface(&painted, &[], &[], 5, 0);
        assert!(vertex.colors_rgb8.iter().all(|&c| c == [188, 255, 0]));
    }
}
