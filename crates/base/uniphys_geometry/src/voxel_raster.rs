use glam::DVec3;

use crate::TriMesh;
use crate::bitset::BitSet;
use crate::tri_box::triangle_overlaps_box;

/// Voxel boxes are grown by this fraction of the pitch before the overlap test, so a triangle
/// lying exactly on a voxel face marks the voxels on both sides regardless of rounding.
pub(crate) const TOUCH_EPSILON: f64 = 1e-6;

/// A regular grid frame: voxel `(i, j, k)` spans `origin + [i, i+1] x [j, j+1] x [k, k+1] * pitch`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridFrame {
    pub origin: DVec3,
    pub pitch: f64,
    pub dims: [usize; 3],
}

impl GridFrame {
    /// Linear index of voxel `(i, j, k)`, x fastest.
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// Total number of voxels.
    pub fn len(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }
}

/// Sets the bit of every voxel whose (slightly grown) box overlaps a triangle of `mesh`.
///
/// Per triangle only the voxels of its bounding box are visited, and of those only the few per
/// column (along the dominant normal axis) that the triangle's plane crosses; each candidate gets
/// the exact separating-axis test.
pub(crate) fn mark_surface(mesh: &TriMesh, frame: &GridFrame, surface: &mut BitSet) {
    let inv = 1.0 / frame.pitch;
    let eps = TOUCH_EPSILON;
    let half = DVec3::splat(0.5 + eps);
    let top = frame.dims.map(|d| d as f64 - 1.0);
    let cell = |x: f64, axis: usize| x.floor().clamp(0.0, top[axis]) as usize;
    for t in 0..mesh.triangle_count() {
        let tri = mesh.corners(t).map(|p| (p - frame.origin) * inv);
        let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        if normal == DVec3::ZERO || !normal.is_finite() {
            continue;
        }
        let lo = tri[0].min(tri[1]).min(tri[2]) - eps;
        let hi = tri[0].max(tri[1]).max(tri[2]) + eps;
        let abs = normal.abs();
        let a = if abs.x >= abs.y && abs.x >= abs.z {
            0
        } else if abs.y >= abs.z {
            1
        } else {
            2
        };
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        // On the plane: x_a = base + kb x_b + kc x_c.
        let base = normal.dot(tri[0]) / normal[a];
        let (kb, kc) = (-normal[b] / normal[a], -normal[c] / normal[a]);
        let mut ijk = [0usize; 3];
        for ib in cell(lo[b], b)..=cell(hi[b], b) {
            let (b0, b1) = (kb * (ib as f64 - eps), kb * (ib as f64 + 1.0 + eps));
            for ic in cell(lo[c], c)..=cell(hi[c], c) {
                let (c0, c1) = (kc * (ic as f64 - eps), kc * (ic as f64 + 1.0 + eps));
                let a_min = (base + b0.min(b1) + c0.min(c1)).max(lo[a]);
                let a_max = (base + b0.max(b1) + c0.max(c1)).min(hi[a]);
                if a_min > a_max + 2.0 * eps {
                    continue;
                }
                ijk[b] = ib;
                ijk[c] = ic;
                for ia in cell(a_min - eps, a)..=cell(a_max + eps, a) {
                    ijk[a] = ia;
                    let index = frame.index(ijk[0], ijk[1], ijk[2]);
                    if surface.get(index) {
                        continue;
                    }
                    let centre = DVec3::new(ijk[0] as f64, ijk[1] as f64, ijk[2] as f64) + 0.5;
                    if triangle_overlaps_box(&tri, centre, half) {
                        surface.insert(index);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(n: usize) -> GridFrame {
        GridFrame {
            origin: DVec3::ZERO,
            pitch: 1.0,
            dims: [n; 3],
        }
    }

    /// Reference: the separating-axis test on every voxel of the grid.
    fn brute_force(mesh: &TriMesh, f: &GridFrame) -> BitSet {
        let mut bits = BitSet::new(f.len());
        let half = DVec3::splat(0.5 + TOUCH_EPSILON);
        for t in 0..mesh.triangle_count() {
            let tri = mesh.corners(t);
            for k in 0..f.dims[2] {
                for j in 0..f.dims[1] {
                    for i in 0..f.dims[0] {
                        let centre = DVec3::new(i as f64, j as f64, k as f64) + 0.5;
                        if triangle_overlaps_box(&tri, centre, half) {
                            bits.insert(f.index(i, j, k));
                        }
                    }
                }
            }
        }
        bits
    }

    #[test]
    fn axis_aligned_triangle_on_a_voxel_face_marks_both_layers() {
        // Right triangle in the plane z = 2 covering x, y in [1, 3] below the diagonal.
        let mesh = TriMesh::new(
            vec![
                DVec3::new(1.0, 1.0, 2.0),
                DVec3::new(3.0, 1.0, 2.0),
                DVec3::new(1.0, 3.0, 2.0),
            ],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let f = frame(5);
        let mut bits = BitSet::new(f.len());
        mark_surface(&mesh, &f, &mut bits);
        // Layers k = 1 and k = 2 touch z = 2; the triangle's closed region touches the voxel
        // columns (i, j) in {0..=3}^2 with i + j <= 4 (box corner (i, j) inside x + y <= 4).
        let columns = (0..=3)
            .flat_map(|i| (0..=3).map(move |j| (i, j)))
            .filter(|&(i, j)| i + j <= 4)
            .count();
        assert_eq!(columns, 13);
        assert_eq!(bits.count(), 2 * columns);
        assert!(bits.get(f.index(1, 1, 1)) && bits.get(f.index(1, 1, 2)));
        assert!(!bits.get(f.index(1, 1, 3)) && !bits.get(f.index(3, 3, 2)));
        assert_eq!(bits, brute_force(&mesh, &f));
    }

    #[test]
    fn slanted_triangles_match_the_brute_force_test() {
        let mesh = TriMesh::new(
            vec![
                DVec3::new(0.3, 0.7, 0.2),
                DVec3::new(6.6, 1.1, 3.9),
                DVec3::new(2.5, 6.8, 6.1),
                DVec3::new(7.5, 7.2, 0.4),
            ],
            vec![[0, 1, 2], [1, 3, 2], [0, 3, 1]],
        )
        .unwrap();
        let f = frame(8);
        let mut bits = BitSet::new(f.len());
        mark_surface(&mesh, &f, &mut bits);
        let expected = brute_force(&mesh, &f);
        assert!(expected.count() > 40);
        assert_eq!(bits, expected);
    }
}
