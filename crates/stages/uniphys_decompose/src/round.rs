//! Whether a part is round about an axis (a wheel, a knob, a dial, a cap): it maps onto itself
//! when turned about a line through its centre along one of its principal directions. Such a
//! part can spin against whatever it is attached to, so it is worth keeping as a part.

use uniphys_geometry::{DQuat, DVec3, TriMesh, principal_axes};

use crate::small_parts::{closest_on_triangle, samples};

/// Turns (radians) the part is checked at: none a multiple of another, so a part with a few-fold
/// symmetry (a square, a hexagonal nut) is not taken for round.
const TURNS_RAD: [f64; 3] = [0.9, 2.0, 2.9];
/// A turned sample lies on the part when it is within this share of the part's diagonal of
/// one of its triangles ...
const ON_SURFACE_FRACTION: f64 = 0.03;
/// ... and the part is round when at least this share of the turned samples does at every turn.
const KEPT_SHARE_MIN: f64 = 0.9;

/// Whether the part made of `faces` of `mesh` is round about one of its principal directions
/// through its samples' mean.
#[must_use]
pub fn is_round(mesh: &TriMesh, faces: &[usize]) -> bool {
    round_axis(mesh, faces).is_some()
}

/// The line (a point on it, its unit direction) the part made of `faces` is round about: one
/// of its principal directions through its samples' mean; `None` when it is round about none.
#[must_use]
pub fn round_axis(mesh: &TriMesh, faces: &[usize]) -> Option<(DVec3, DVec3)> {
    let surface = Surface::of(mesh, faces)?;
    let centre = surface.points.iter().sum::<DVec3>() / surface.points.len() as f64;
    principal_axes(&surface.points)
        .into_iter()
        .find(|&axis| surface.maps_onto_itself(centre, axis))
        .map(|axis| (centre, axis))
}

/// Whether the part made of `faces` maps onto itself when turned about the line through
/// `centre` along unit `axis`: at three turns, none a multiple of another, 90 % of its samples
/// land within 3 % of its diagonal of its own surface.
#[must_use]
pub fn round_about(mesh: &TriMesh, faces: &[usize], centre: DVec3, axis: DVec3) -> bool {
    Surface::of(mesh, faces).is_some_and(|surface| surface.maps_onto_itself(centre, axis))
}

/// A part's samples and triangles, and how near a turned sample must land to its surface.
struct Surface {
    points: Vec<DVec3>,
    triangles: Vec<[DVec3; 3]>,
    tolerance2: f64,
}

impl Surface {
    /// `None` for a part with too few samples to judge.
    fn of(mesh: &TriMesh, faces: &[usize]) -> Option<Self> {
        let points = samples(mesh, faces);
        if points.len() < 8 {
            return None;
        }
        let diagonal = uniphys_geometry::Aabb::from_points(&points).diagonal();
        Some(Self {
            triangles: faces.iter().map(|&f| mesh.corners(f)).collect(),
            tolerance2: (ON_SURFACE_FRACTION * diagonal).powi(2),
            points,
        })
    }

    /// Whether at every one of [`TURNS_RAD`] about the line through `centre` along `axis`, at
    /// least [`KEPT_SHARE_MIN`] of the samples land on the surface.
    fn maps_onto_itself(&self, centre: DVec3, axis: DVec3) -> bool {
        TURNS_RAD.iter().all(|&angle| {
            let turn = DQuat::from_axis_angle(axis, angle);
            let kept = self
                .points
                .iter()
                .filter(|&&p| {
                    let q = centre + turn * (p - centre);
                    self.triangles
                        .iter()
                        .any(|t| closest_on_triangle(q, t).distance_squared(q) <= self.tolerance2)
                })
                .count();
            kept as f64 >= KEPT_SHARE_MIN * self.points.len() as f64
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn faces(mesh: &TriMesh) -> Vec<usize> {
        (0..mesh.triangle_count()).collect()
    }

    #[test]
    fn a_cylinder_is_round_and_a_bar_or_a_square_block_is_not() {
        let wheel = uniphys_examples::shapes::cylinder(0.3, 0.0, 0.1, 48);
        assert!(is_round(&wheel, &faces(&wheel)));
        let bar = TriMesh::cuboid(DVec3::ZERO, DVec3::new(0.4, 0.05, 0.05));
        assert!(!is_round(&bar, &faces(&bar)));
        let block = TriMesh::cuboid(DVec3::ZERO, DVec3::new(0.2, 0.2, 0.05));
        assert!(!is_round(&block, &faces(&block)));
    }

    #[test]
    fn a_cylinder_is_round_about_its_own_line_only() {
        let wheel = uniphys_examples::shapes::cylinder(0.3, 0.0, 0.1, 48);
        let all = faces(&wheel);
        let (centre, axis) = round_axis(&wheel, &all).expect("round");
        assert!(axis.dot(DVec3::Z).abs() > 0.999, "{axis}");
        assert!(round_about(&wheel, &all, centre, axis));
        assert!(!round_about(&wheel, &all, centre + DVec3::X * 0.2, axis));
        assert!(!round_about(&wheel, &all, centre, DVec3::X));
    }
}
