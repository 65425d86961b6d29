//! Thin-walled parts: how much material a part's surface stands for when the part is a wall, not
//! a solid. Each point of the surface holds material up to half the gap to the next surface
//! behind or in front of it (a wall drawn with both its faces) and at most the wall thickness
//! of the part's material (a sheet drawn once, or the skin of a hollow body).

use std::collections::HashSet;

use glam::DVec3;
use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};

use crate::mass::{Moments, outer};
use crate::sampling::AreaSampler;
use crate::{MassProperties, SplitMix64, TriMesh};

/// A part's surface sampled with the gap to the nearest other surface along the normal at each
/// sample, in both directions.
#[derive(Debug, Clone, PartialEq)]
pub struct WallSamples {
    /// Area of the distinct triangles, m^2 (a panel drawn once per side counts once).
    pub area_m2: f64,
    /// Sample points, uniform over the distinct triangles, metres.
    points: Vec<DVec3>,
    /// The gap at each sample, m (`f64::INFINITY` when no surface faces it).
    gaps_m: Vec<f64>,
}

impl WallSamples {
    /// `count` samples of the surface of `mesh` (vertices welded at 1e-9 of the bounds diagonal,
    /// coincident triangles once) with their gaps; deterministic for a `seed`. `None` when the
    /// mesh has no area.
    #[must_use]
    pub fn of_mesh(mesh: &TriMesh, count: usize, seed: u64) -> Option<Self> {
        let diagonal = mesh.bounds().diagonal();
        if !(diagonal.is_finite() && diagonal > 0.0) || count == 0 {
            return None;
        }
        let welded = mesh.welded(1e-9 * diagonal);
        let mut seen = HashSet::with_capacity(welded.triangle_count());
        let distinct: Vec<usize> = (0..welded.triangle_count())
            .filter(|&i| {
                let mut key = welded.triangles[i];
                key.sort_unstable();
                seen.insert(key)
            })
            .collect();
        let surface = welded.submesh(&distinct);
        let area_m2 = surface.area();
        let sampler = AreaSampler::new(&surface)?;
        let origin = surface.bounds().center();
        let vertices: Vec<Vector> = welded
            .positions
            .iter()
            .map(|p| to_f32(*p - origin))
            .collect();
        // Rays see every triangle, the repeated ones too, so a sheet's twin is skipped only by
        // starting the ray just off the surface.
        let bvh = parry3d::shape::TriMesh::new(vertices, welded.triangles.clone()).ok()?;
        let start_off = 1e-5 * diagonal;
        let mut rng = SplitMix64::new(seed);
        let mut points = Vec::with_capacity(count);
        let mut gaps_m = Vec::with_capacity(count);
        for _ in 0..count {
            let (face, w) = sampler.sample(&mut rng);
            let [a, b, c] = surface.corners(face);
            let point = a * w[0] + b * w[1] + c * w[2];
            let normal = surface.face_normal(face);
            let gap = [normal, -normal]
                .into_iter()
                .filter_map(|dir| {
                    let from = point - origin + dir * start_off;
                    let ray = Ray::new(to_f32(from), to_f32(dir));
                    bvh.cast_local_ray(&ray, diagonal as f32, false)
                        .map(|toi| f64::from(toi) + start_off)
                })
                .fold(f64::INFINITY, f64::min);
            points.push(point);
            gaps_m.push(gap);
        }
        Some(Self {
            area_m2,
            points,
            gaps_m,
        })
    }

    /// Mass properties, per unit density, of the material the surface stands for when its walls
    /// are at most `wall_m` thick. `None` without samples.
    #[must_use]
    pub fn with_wall(&self, wall_m: f64) -> Option<MassProperties> {
        if self.points.is_empty() || !(wall_m.is_finite() && wall_m > 0.0) {
            return None;
        }
        let area_each = self.area_m2 / self.points.len() as f64;
        let reference = self.points[0];
        let mut moments = Moments::default();
        for (p, gap) in self.points.iter().zip(&self.gaps_m) {
            let volume = area_each * (0.5 * gap).min(wall_m);
            let r = *p - reference;
            moments.volume += volume;
            moments.first += volume * r;
            moments.second += outer(r) * volume;
        }
        (moments.volume > 0.0).then(|| moments.about_centre_of_mass(reference))
    }
}

fn to_f32(p: DVec3) -> Vector {
    Vector::new(p.x as f32, p.y as f32, p.z as f32)
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;
    use crate::test_shapes::{open_box, unit_box};

    fn panel(both_sides: bool) -> TriMesh {
        let mut triangles = vec![[0, 1, 2], [0, 2, 3]];
        if both_sides {
            triangles.extend([[0, 2, 1], [0, 3, 2]]);
        }
        TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            triangles,
        )
        .unwrap()
    }

    #[test]
    fn a_closed_cube_is_a_skin_of_the_wall_thickness_with_the_thin_shell_inertia() {
        let cube = unit_box(DVec3::splat(-0.5), DVec3::splat(0.5));
        let walls = WallSamples::of_mesh(&cube, 4000, 7).unwrap();
        assert!((walls.area_m2 - 6.0).abs() < 1e-12);
        let skin = walls.with_wall(0.01).unwrap();
        assert!((skin.volume_m3 - 0.06).abs() < 1e-9, "{}", skin.volume_m3);
        assert!(skin.com.length() < 0.02, "{:?}", skin.com);
        // A thin cubic shell of side s and mass m: I = 5/18 m s^2 about each axis.
        let expected = 5.0 / 18.0 * 0.06;
        let inertia: DMat3 = skin.inertia_about_com_per_density;
        for d in [inertia.x_axis.x, inertia.y_axis.y, inertia.z_axis.z] {
            assert!((d / expected - 1.0).abs() < 0.05, "{d} vs {expected}");
        }
    }

    #[test]
    fn a_wall_drawn_with_both_faces_holds_the_material_between_them() {
        // A board 16 mm thick: each large face holds half the gap; its edges a wall each.
        let board = unit_box(DVec3::ZERO, DVec3::new(0.6, 0.016, 0.8));
        let walls = WallSamples::of_mesh(&board, 8000, 3).unwrap();
        let volume = walls.with_wall(0.018).unwrap().volume_m3;
        let faces = 0.6 * 0.8 * 0.016;
        let edges = 2.0 * (0.6 + 0.8) * 0.016 * 0.018;
        assert!(
            ((volume - (faces + edges)) / faces).abs() < 0.05,
            "{volume} vs {}",
            faces + edges
        );
    }

    #[test]
    fn a_sheet_drawn_once_or_on_both_sides_is_one_wall() {
        for both in [false, true] {
            let walls = WallSamples::of_mesh(&panel(both), 500, 1).unwrap();
            assert!((walls.area_m2 - 1.0).abs() < 1e-12);
            let wall = walls.with_wall(0.002).unwrap();
            assert!((wall.volume_m3 - 0.002).abs() < 1e-12, "both sides: {both}");
            assert!((wall.com - DVec3::new(0.5, 0.5, 0.0)).length() < 0.05);
        }
    }

    #[test]
    fn an_open_box_has_five_faces_and_its_centre_of_mass_at_their_mean() {
        let walls = WallSamples::of_mesh(&open_box(), 4000, 5).unwrap();
        assert!((walls.area_m2 - 5.0).abs() < 1e-9, "{}", walls.area_m2);
        let wall = walls.with_wall(0.01).unwrap();
        // The bottom at z = 0 and four sides centred at z = 0.5: (4 x 0.5) / 5.
        assert!((wall.com.z - 0.4).abs() < 0.02, "{:?}", wall.com);
        assert!((wall.volume_m3 - 0.05).abs() < 1e-9);
    }
}
