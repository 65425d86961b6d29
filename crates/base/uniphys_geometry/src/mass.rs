use glam::{DMat3, DVec3};

use crate::TriMesh;

/// Volume, centre of mass and inertia of a solid of uniform density 1 kg/m^3.
///
/// Multiply by a density with [`MassProperties::mass_kg`] and [`MassProperties::inertia_kg_m2`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Enclosed volume, m^3.
    pub volume_m3: f64,
    /// Centre of mass (the centroid of the volume), metres, in the mesh frame.
    pub com: DVec3,
    /// Inertia tensor about the centre of mass, axes of the mesh frame, for density 1 kg/m^3
    /// (so in m^5; times a density in kg/m^3 gives kg m^2).
    pub inertia_about_com_per_density: DMat3,
}

impl MassProperties {
    /// Exact mass properties of a closed mesh by the divergence theorem (a sum of signed
    /// tetrahedra from a reference point to every triangle).
    ///
    /// Vertices are first welded with a tolerance of 1e-9 times the bounds diagonal. Returns
    /// `None` if the welded mesh is not closed (see [`TriMesh::is_closed`]) or its volume is not
    /// positive (inside-out or flat, below 1e-12 of the bounding cube of the diagonal).
    #[must_use]
    pub fn from_closed_mesh(mesh: &TriMesh) -> Option<Self> {
        let diagonal = mesh.bounds().diagonal();
        if !(diagonal.is_finite() && diagonal > 0.0) {
            return None;
        }
        let welded = mesh.welded(1e-9 * diagonal);
        if !welded.is_closed() {
            return None;
        }
        let reference = welded.bounds().center();
        let mut moments = Moments::default();
        for i in 0..welded.triangle_count() {
            let [a, b, c] = welded.corners(i).map(|p| p - reference);
            moments.add_origin_tetrahedron(a, b, c);
        }
        if moments.volume <= 1e-12 * diagonal.powi(3) {
            return None;
        }
        Some(moments.about_centre_of_mass(reference))
    }

    /// Mass in kg for a uniform density in kg/m^3.
    #[must_use]
    pub fn mass_kg(&self, density_kg_per_m3: f64) -> f64 {
        self.volume_m3 * density_kg_per_m3
    }

    /// Inertia tensor about the centre of mass in kg m^2 for a uniform density in kg/m^3.
    #[must_use]
    pub fn inertia_kg_m2(&self, density_kg_per_m3: f64) -> DMat3 {
        self.inertia_about_com_per_density * density_kg_per_m3
    }

    /// The body made of `bodies`, each `(properties, fraction)` filled to that fraction of its
    /// volume (a fraction scales its volume and inertia alike), by the parallel-axis theorem.
    /// `None` when the total volume is not positive.
    #[must_use]
    pub fn combined(bodies: &[(Self, f64)]) -> Option<Self> {
        let volume: f64 = bodies.iter().map(|(b, f)| b.volume_m3 * f).sum();
        if !(volume.is_finite() && volume > 0.0) {
            return None;
        }
        let com = bodies
            .iter()
            .map(|(b, f)| b.com * (b.volume_m3 * f))
            .sum::<DVec3>()
            / volume;
        let inertia = bodies
            .iter()
            .map(|(b, f)| {
                let d = b.com - com;
                let shift = DMat3::from_diagonal(DVec3::splat(d.length_squared())) - outer(d);
                (b.inertia_about_com_per_density + shift * b.volume_m3) * *f
            })
            .fold(DMat3::ZERO, |a, b| a + b);
        Some(Self {
            volume_m3: volume,
            com,
            inertia_about_com_per_density: symmetrised(inertia),
        })
    }
}

/// Zeroth, first and second volume moments about a reference point, for density 1.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moments {
    /// Integral of 1.
    pub volume: f64,
    /// Integral of x.
    pub first: DVec3,
    /// Integral of x x^T.
    pub second: DMat3,
}

impl Default for Moments {
    // Not derived: `DMat3::default()` is the identity.
    fn default() -> Self {
        Self {
            volume: 0.0,
            first: DVec3::ZERO,
            second: DMat3::ZERO,
        }
    }
}

impl Moments {
    /// Adds the signed tetrahedron (0, a, b, c); positive when (a, b, c) winds counter-clockwise
    /// seen from outside, i.e. away from the origin.
    pub fn add_origin_tetrahedron(&mut self, a: DVec3, b: DVec3, c: DVec3) {
        let v = a.dot(b.cross(c)) / 6.0;
        let s = a + b + c;
        self.volume += v;
        self.first += v * s / 4.0;
        // Integral of x x^T over a tetrahedron with one vertex at the origin:
        // V/20 (a a^T + b b^T + c c^T + s s^T).
        self.second += (outer(a) + outer(b) + outer(c) + outer(s)) * (v / 20.0);
    }

    /// Mass properties, given that the moments were taken about `reference`. The volume must be
    /// positive.
    pub fn about_centre_of_mass(&self, reference: DVec3) -> MassProperties {
        let d = self.first / self.volume;
        let central = self.second - outer(d) * self.volume;
        let inertia = DMat3::from_diagonal(DVec3::splat(trace(&central))) - central;
        MassProperties {
            volume_m3: self.volume,
            com: reference + d,
            inertia_about_com_per_density: symmetrised(inertia),
        }
    }
}

/// The outer product v v^T.
pub(crate) fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

fn trace(m: &DMat3) -> f64 {
    m.x_axis.x + m.y_axis.y + m.z_axis.z
}

fn symmetrised(m: DMat3) -> DMat3 {
    (m + m.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tests::unit_box;

    fn assert_mat_close(a: DMat3, b: DMat3, tol: f64) {
        for c in 0..3 {
            assert!((a.col(c) - b.col(c)).length() < tol, "{a:?}\nvs\n{b:?}");
        }
    }

    #[test]
    fn box_has_exact_volume_centre_and_inertia() {
        // 1 x 2 x 3 box: V = 6; I/rho = V/12 (b^2 + c^2) etc. = (13/2, 10/2, 5/2).
        let m = MassProperties::from_closed_mesh(&unit_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)))
            .unwrap();
        assert!((m.volume_m3 - 6.0).abs() < 1e-12);
        assert!((m.com - DVec3::new(0.5, 1.0, 1.5)).length() < 1e-12);
        assert_mat_close(
            m.inertia_about_com_per_density,
            DMat3::from_diagonal(DVec3::new(6.5, 5.0, 2.5)),
            1e-12,
        );
        // Density 1000 kg/m^3: 6000 kg, Ixx = 6500 kg m^2.
        assert!((m.mass_kg(1000.0) - 6000.0).abs() < 1e-9);
        assert!((m.inertia_kg_m2(1000.0).x_axis.x - 6500.0).abs() < 1e-9);
    }

    #[test]
    fn offset_box_moves_the_centre_but_not_the_central_inertia() {
        let min = DVec3::new(10.0, -4.0, 2.0);
        let m = MassProperties::from_closed_mesh(&unit_box(min, min + DVec3::ONE)).unwrap();
        assert!((m.volume_m3 - 1.0).abs() < 1e-12);
        assert!((m.com - DVec3::new(10.5, -3.5, 2.5)).length() < 1e-12);
        // Unit cube: I/rho = 1/12 (1 + 1) = 1/6 on every axis.
        assert_mat_close(
            m.inertia_about_com_per_density,
            DMat3::from_diagonal(DVec3::splat(1.0 / 6.0)),
            1e-12,
        );
    }

    #[test]
    fn rotated_box_has_off_diagonal_inertia() {
        // Rotating the 1x2x3 box by 90 degrees about z swaps the x and y moments.
        let mesh = unit_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0))
            .transformed(&glam::DMat4::from_rotation_z(std::f64::consts::FRAC_PI_2));
        let m = MassProperties::from_closed_mesh(&mesh).unwrap();
        assert_mat_close(
            m.inertia_about_com_per_density,
            DMat3::from_diagonal(DVec3::new(5.0, 6.5, 2.5)),
            1e-9,
        );
    }

    #[test]
    fn two_boxes_combined_are_the_box_they_make() {
        let whole =
            MassProperties::from_closed_mesh(&unit_box(DVec3::ZERO, DVec3::new(2.0, 1.0, 1.0)))
                .unwrap();
        let left = MassProperties::from_closed_mesh(&unit_box(DVec3::ZERO, DVec3::ONE)).unwrap();
        let right =
            MassProperties::from_closed_mesh(&unit_box(DVec3::X, DVec3::new(2.0, 1.0, 1.0)))
                .unwrap();
        let both = MassProperties::combined(&[(left, 1.0), (right, 1.0)]).unwrap();
        assert!((both.volume_m3 - whole.volume_m3).abs() < 1e-12);
        assert!((both.com - whole.com).length() < 1e-12);
        assert_mat_close(
            both.inertia_about_com_per_density,
            whole.inertia_about_com_per_density,
            1e-12,
        );
        let half = MassProperties::combined(&[(left, 0.5)]).unwrap();
        assert!((half.volume_m3 - 0.5).abs() < 1e-12);
        assert!(MassProperties::combined(&[(left, 0.0)]).is_none());
    }

    #[test]
    fn open_or_inside_out_meshes_have_no_exact_properties() {
        let closed = unit_box(DVec3::ZERO, DVec3::ONE);
        let open = closed.submesh(&(0..11).collect::<Vec<_>>());
        assert!(MassProperties::from_closed_mesh(&open).is_none());
        let mut inverted = closed.clone();
        for t in &mut inverted.triangles {
            t.swap(1, 2);
        }
        assert!(MassProperties::from_closed_mesh(&inverted).is_none());
        assert!(MassProperties::from_closed_mesh(&TriMesh::default()).is_none());
    }
}
