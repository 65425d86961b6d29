use std::collections::HashMap;

use glam::{DMat4, DVec3};

use crate::{Aabb, GeometryError, GeometryResult};

/// An indexed triangle mesh with optional per-vertex UVs and colours and per-face materials.
///
/// Invariants (checked by [`TriMesh::new`] and the `with_*` builders): coordinates are finite,
/// indices are in range, attribute lengths match. Triangles wind counter-clockwise seen from
/// outside, so face normals point out of a closed mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates per vertex (glTF convention: v points down the image).
    pub uvs: Option<Vec<[f32; 2]>>,
    /// Linear RGBA colour per vertex, components in [0, 1].
    pub vertex_colors: Option<Vec<[f32; 4]>>,
    /// Material index per triangle into the owning [`crate::MeshAsset::materials`], if any.
    pub face_materials: Option<Vec<u32>>,
}

impl TriMesh {
    /// Builds a mesh, checking that coordinates are finite and indices in range.
    pub fn new(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> GeometryResult<Self> {
        let mesh = Self {
            positions,
            triangles,
            ..Self::default()
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// The closed axis-aligned box between the corners `min` and `max` (finite, `min < max`), with
    /// outward winding.
    #[must_use]
    pub fn cuboid(min: DVec3, max: DVec3) -> Self {
        let corner = |x: usize, y: usize, z: usize| {
            DVec3::new([min.x, max.x][x], [min.y, max.y][y], [min.z, max.z][z])
        };
        let positions = vec![
            corner(0, 0, 0),
            corner(1, 0, 0),
            corner(1, 1, 0),
            corner(0, 1, 0),
            corner(0, 0, 1),
            corner(1, 0, 1),
            corner(1, 1, 1),
            corner(0, 1, 1),
        ];
        // Two triangles per face: -z, +z, -y, +y, -x, +x.
        let triangles = vec![
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [3, 7, 6],
            [3, 6, 2],
            [0, 4, 7],
            [0, 7, 3],
            [1, 2, 6],
            [1, 6, 5],
        ];
        Self {
            positions,
            triangles,
            ..Self::default()
        }
    }

    /// Attaches per-vertex texture coordinates.
    pub fn with_uvs(mut self, uvs: Vec<[f32; 2]>) -> GeometryResult<Self> {
        check_len("uvs", uvs.len(), self.positions.len())?;
        self.uvs = Some(uvs);
        Ok(self)
    }

    /// Attaches per-vertex colours.
    pub fn with_vertex_colors(mut self, colors: Vec<[f32; 4]>) -> GeometryResult<Self> {
        check_len("vertex colours", colors.len(), self.positions.len())?;
        self.vertex_colors = Some(colors);
        Ok(self)
    }

    /// Attaches a material index per triangle.
    pub fn with_face_materials(mut self, materials: Vec<u32>) -> GeometryResult<Self> {
        check_len("face materials", materials.len(), self.triangles.len())?;
        self.face_materials = Some(materials);
        Ok(self)
    }

    /// Checks the invariants listed on the type.
    pub fn validate(&self) -> GeometryResult<()> {
        if let Some(index) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::NonFiniteVertex { index });
        }
        let vertex_count = self.positions.len();
        for (triangle, tri) in self.triangles.iter().enumerate() {
            if let Some(&vertex) = tri.iter().find(|&&v| v as usize >= vertex_count) {
                return Err(GeometryError::IndexOutOfRange {
                    triangle,
                    vertex,
                    vertex_count,
                });
            }
        }
        if let Some(uvs) = &self.uvs {
            check_len("uvs", uvs.len(), vertex_count)?;
        }
        if let Some(colors) = &self.vertex_colors {
            check_len("vertex colours", colors.len(), vertex_count)?;
        }
        if let Some(materials) = &self.face_materials {
            check_len("face materials", materials.len(), self.triangles.len())?;
        }
        Ok(())
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The three corner positions of triangle `i`.
    #[must_use]
    pub fn corners(&self, i: usize) -> [DVec3; 3] {
        let [a, b, c] = self.triangles[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Twice the area times the unit normal of triangle `i` (the raw cross product).
    #[must_use]
    pub fn scaled_normal(&self, i: usize) -> DVec3 {
        let [a, b, c] = self.corners(i);
        (b - a).cross(c - a)
    }

    /// Unit normal of triangle `i`, or zero for a degenerate triangle.
    #[must_use]
    pub fn face_normal(&self, i: usize) -> DVec3 {
        self.scaled_normal(i).normalize_or_zero()
    }

    /// Area of triangle `i`.
    #[must_use]
    pub fn face_area(&self, i: usize) -> f64 {
        0.5 * self.scaled_normal(i).length()
    }

    /// Total surface area.
    #[must_use]
    pub fn area(&self) -> f64 {
        (0..self.triangles.len()).map(|i| self.face_area(i)).sum()
    }

    /// Bounds of the vertices that triangles use.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.triangles
            .iter()
            .flatten()
            .fold(Aabb::EMPTY, |b, &v| b.grown(self.positions[v as usize]))
    }

    /// Whether every edge is shared by exactly two triangles with opposite orientation, i.e. the
    /// mesh is a closed, consistently oriented 2-manifold (vertices welded by index).
    #[must_use]
    pub fn is_closed(&self) -> bool {
        if self.triangles.is_empty() {
            return false;
        }
        let mut directed: HashMap<(u32, u32), u32> =
            HashMap::with_capacity(self.triangles.len() * 3);
        for &[a, b, c] in &self.triangles {
            for edge in [(a, b), (b, c), (c, a)] {
                *directed.entry(edge).or_insert(0) += 1;
            }
        }
        directed
            .iter()
            .all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1))
    }

    /// A copy with all vertices merged that share a position exactly (after the given rounding
    /// tolerance, metres), so meshes split at UV or normal seams can be checked for closedness.
    #[must_use]
    pub fn welded(&self, tolerance: f64) -> Self {
        let inv = if tolerance > 0.0 {
            1.0 / tolerance
        } else {
            1.0
        };
        let mut index_of: HashMap<[i64; 3], u32> = HashMap::new();
        let mut remap = Vec::with_capacity(self.positions.len());
        let mut positions = Vec::new();
        for p in &self.positions {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "quantised key; coordinates are bounded"
            )]
            let key = [
                (p.x * inv).round() as i64,
                (p.y * inv).round() as i64,
                (p.z * inv).round() as i64,
            ];
            let next = u32::try_from(positions.len()).unwrap_or(u32::MAX);
            let idx = *index_of.entry(key).or_insert_with(|| {
                positions.push(*p);
                next
            });
            remap.push(idx);
        }
        let triangles = self
            .triangles
            .iter()
            .map(|t| t.map(|v| remap[v as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        Self {
            positions,
            triangles,
            ..Self::default()
        }
    }

    /// A copy transformed by an affine matrix; winding is flipped when the matrix mirrors.
    #[must_use]
    pub fn transformed(&self, m: &DMat4) -> Self {
        let mut out = self.clone();
        for p in &mut out.positions {
            *p = m.transform_point3(*p);
        }
        if m.determinant() < 0.0 {
            for t in &mut out.triangles {
                t.swap(1, 2);
            }
        }
        out
    }

    /// A copy without triangles whose area is at most `min_area`.
    #[must_use]
    pub fn without_degenerate(&self, min_area: f64) -> Self {
        let keep: Vec<usize> = (0..self.triangles.len())
            .filter(|&i| self.face_area(i) > min_area)
            .collect();
        self.submesh(&keep)
    }

    /// The mesh made of the given triangles, with unused vertices dropped.
    #[must_use]
    pub fn submesh(&self, faces: &[usize]) -> Self {
        let mut remap: HashMap<u32, u32> = HashMap::new();
        let mut order: Vec<u32> = Vec::new();
        let triangles: Vec<[u32; 3]> = faces
            .iter()
            .map(|&f| {
                self.triangles[f].map(|v| {
                    *remap.entry(v).or_insert_with(|| {
                        order.push(v);
                        u32::try_from(order.len() - 1).unwrap_or(u32::MAX)
                    })
                })
            })
            .collect();
        let pick = |i: &u32| *i as usize;
        Self {
            positions: order.iter().map(|i| self.positions[pick(i)]).collect(),
            triangles,
            uvs: self
                .uvs
                .as_ref()
                .map(|a| order.iter().map(|i| a[pick(i)]).collect()),
            vertex_colors: self
                .vertex_colors
                .as_ref()
                .map(|a| order.iter().map(|i| a[pick(i)]).collect()),
            face_materials: self
                .face_materials
                .as_ref()
                .map(|a| faces.iter().map(|&f| a[f]).collect()),
        }
    }

    /// Concatenates meshes. An attribute is kept only if every input has it.
    #[must_use]
    pub fn merge<'a>(meshes: impl IntoIterator<Item = &'a TriMesh>) -> Self {
        let meshes: Vec<&TriMesh> = meshes.into_iter().collect();
        let all = |f: fn(&TriMesh) -> bool| !meshes.is_empty() && meshes.iter().all(|m| f(m));
        let (has_uv, has_color, has_mat) = (
            all(|m| m.uvs.is_some()),
            all(|m| m.vertex_colors.is_some()),
            all(|m| m.face_materials.is_some()),
        );
        let mut out = Self::default();
        for m in meshes {
            let offset = u32::try_from(out.positions.len()).unwrap_or(u32::MAX);
            out.positions.extend_from_slice(&m.positions);
            out.triangles
                .extend(m.triangles.iter().map(|t| t.map(|v| v + offset)));
            if has_uv {
                out.uvs
                    .get_or_insert_with(Vec::new)
                    .extend(m.uvs.iter().flatten());
            }
            if has_color {
                out.vertex_colors
                    .get_or_insert_with(Vec::new)
                    .extend(m.vertex_colors.iter().flatten());
            }
            if has_mat {
                out.face_materials
                    .get_or_insert_with(Vec::new)
                    .extend(m.face_materials.iter().flatten());
            }
        }
        out
    }
}

fn check_len(attribute: &'static str, got: usize, expected: usize) -> GeometryResult<()> {
    if got == expected {
        Ok(())
    } else {
        Err(GeometryError::AttributeLength {
            attribute,
            got,
            expected,
        })
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// An axis-aligned closed box with outward winding, for tests.
    pub(crate) fn unit_box(min: DVec3, max: DVec3) -> TriMesh {
        TriMesh::cuboid(min, max)
    }

    #[test]
    fn box_is_closed_with_outward_normals_and_correct_area() {
        let m = unit_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0));
        assert!(m.is_closed());
        assert!((m.area() - 2.0 * (2.0 + 3.0 + 6.0)).abs() < 1e-12);
        assert!((m.face_normal(2) - DVec3::Z).length() < 1e-12);
        let open = m.submesh(&(0..11).collect::<Vec<_>>());
        assert!(!open.is_closed());
    }

    #[test]
    fn new_rejects_nan_and_out_of_range_indices() {
        assert_eq!(
            TriMesh::new(vec![DVec3::new(f64::NAN, 0.0, 0.0)], vec![]),
            Err(GeometryError::NonFiniteVertex { index: 0 })
        );
        assert!(matches!(
            TriMesh::new(vec![DVec3::ZERO; 3], vec![[0, 1, 3]]),
            Err(GeometryError::IndexOutOfRange {
                triangle: 0,
                vertex: 3,
                vertex_count: 3
            })
        ));
    }

    #[test]
    fn mirroring_transform_keeps_normals_outward() {
        let m = unit_box(DVec3::ZERO, DVec3::ONE);
        let mirrored = m.transformed(&DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)));
        assert!(mirrored.is_closed());
        // +z face stays +z after mirroring x.
        assert!((mirrored.face_normal(2) - DVec3::Z).length() < 1e-12);
    }

    #[test]
    fn welding_closes_a_box_split_at_seams() {
        let m = unit_box(DVec3::ZERO, DVec3::ONE);
        // Unweld: every triangle gets its own three vertices.
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for i in 0..m.triangle_count() {
            let base = u32::try_from(positions.len()).unwrap();
            positions.extend(m.corners(i));
            triangles.push([base, base + 1, base + 2]);
        }
        let split = TriMesh::new(positions, triangles).unwrap();
        assert!(!split.is_closed());
        assert!(split.welded(1e-9).is_closed());
    }
}
