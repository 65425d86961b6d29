//! A round part spun about a line it is not round about, measured at rest.
//!
//! A part that turns without limit (a knob, a wheel, a cap, a lens ring) spins about the axis
//! it is round about: turned, it lands on itself. The same part flipped about a line across it
//! (a wheel about its diameter, a knob on a long stem about a line through its disc) often
//! passes its sweep, since nothing stands close enough around it to be hit, yet no real
//! mechanism turns it that way. A part that is round about no line at all (a faucet's spout
//! swivelling on its collar) says nothing either way and is not judged.

use uniphys_geometry::{DVec3, projection_range};

use crate::fit::ROUND_RESIDUAL_MAX;
use crate::held::farthest_from_line_m;
use crate::scene::Scene;

/// How a part turned without limit sits against the line it is round about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffRoundSpin {
    /// The roundness residual about the joint's line (see `fit::spin_residual`), a share of the
    /// moving parts' diagonal.
    pub residual: f64,
    /// The residual about the line the moving parts are round about (at most
    /// `fit::ROUND_RESIDUAL_MAX`).
    pub round_residual: f64,
    /// That line's direction (unit) ...
    pub round_axis: DVec3,
    /// ... and a point on it, object frame, metres.
    pub round_point: DVec3,
}

/// The line a part is round about runs across the joint's when their |cosine| is below this
/// (60 degrees apart): a line nearer the joint's is the same spin, fitted less exactly (a
/// decomposed knob's spin line a few degrees off its round axis), which its correction refines
/// and no rule should reject.
const OFF_ROUND_COS_MAX: f64 = 0.5;

/// The spin of the moving group (parts `moving_parts`, sampled at `moving`) about the joint's
/// line along `axis`, where its roundness residual is `residual` (`fit::spin_residual`),
/// against the line it is round about, or `None` when it is round about the joint's line (a
/// residual at most `residual_min`), about no line at all, about a line near the joint's
/// ([`OFF_ROUND_COS_MAX`]), or longer along that line than across it (a rod, or a knob merged
/// with a bar by a rough decomposition).
pub(crate) fn off_round_spin(
    scene: &Scene,
    moving_parts: &[usize],
    moving: &[DVec3],
    axis: DVec3,
    residual: f64,
    residual_min: f64,
) -> Option<OffRoundSpin> {
    let axis = axis.normalize_or_zero();
    if moving.len() < 3 || axis == DVec3::ZERO {
        return None;
    }
    if residual <= residual_min.max(ROUND_RESIDUAL_MAX) {
        return None;
    }
    let (round_axis, round_point, round_residual) = scene.round_line(moving_parts, moving)?;
    let across = round_axis.dot(axis).abs() < OFF_ROUND_COS_MAX;
    // A disc or a drum (a wheel, a knob, a cap) is no longer along its round axis than across
    // it; a rod is round about its length, and turned across it swings as a lever does.
    (across && squat_about(moving, round_point, round_axis)).then_some(OffRoundSpin {
        residual,
        round_residual,
        round_axis,
        round_point,
    })
}

/// Whether the part sampled at `points` is a disc or a drum about the line through `point`
/// along unit `axis`: no longer along it than across it (a wheel, a knob, a cap, a button), not
/// a rod, a lever or a blade lying along it. A part's roundness residual is a share of its
/// diagonal, so a thin part lying along the line seems round about it whatever its section.
pub(crate) fn squat_about(points: &[DVec3], point: DVec3, axis: DVec3) -> bool {
    let (lo, hi) = projection_range(points, axis);
    hi - lo <= 2.0 * farthest_from_line_m(points, point, axis)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use uniphys_geometry::TriMesh;

    use super::*;
    use crate::fit::spin_residual;

    /// A closed cylinder (a wheel) of radius 0.3 and width 0.1 about the y axis through
    /// `centre`.
    fn wheel(centre: DVec3) -> TriMesh {
        let n = 48u32;
        let mut positions = vec![
            centre + DVec3::new(0.0, -0.05, 0.0),
            centre + DVec3::new(0.0, 0.05, 0.0),
        ];
        for i in 0..n {
            let a = 2.0 * PI * f64::from(i) / f64::from(n);
            for y in [-0.05, 0.05] {
                positions.push(centre + DVec3::new(0.3 * a.cos(), y, 0.3 * a.sin()));
            }
        }
        let mut triangles = Vec::new();
        for i in 0..n {
            let (a0, a1) = (2 + 2 * i, 2 + 2 * ((i + 1) % n));
            triangles.extend([
                [0, a1, a0],
                [1, a0 + 1, a1 + 1],
                [a0, a1, a0 + 1],
                [a1, a1 + 1, a0 + 1],
            ]);
        }
        TriMesh::new(positions, triangles).expect("wheel")
    }

    #[test]
    fn a_wheel_spun_about_its_axle_is_not_judged_and_about_its_diameter_is() {
        let centre = DVec3::new(0.5, -0.2, 0.3);
        let s = Scene::of_convex_parts(&[wheel(centre)], 2000);
        let points = s.points_of(&[0]);
        let along_axle = spin_residual(&points, DVec3::Y, centre);
        assert!(off_round_spin(&s, &[0], &points, DVec3::Y, along_axle, 0.06).is_none());
        let across = spin_residual(&points, DVec3::Z, centre);
        let flipped =
            off_round_spin(&s, &[0], &points, DVec3::Z, across, 0.06).expect("flipped wheel");
        assert!(flipped.residual > 0.06, "{flipped:?}");
        assert!(flipped.round_axis.dot(DVec3::Y).abs() > 0.99, "{flipped:?}");
        let off_line = (flipped.round_point - centre)
            .reject_from_normalized(DVec3::Y)
            .length();
        assert!(off_line < 0.01, "{flipped:?}");
    }

    #[test]
    fn a_part_round_about_no_line_is_not_judged() {
        // An L of two bars: a spout swivelling on its collar.
        let upright = TriMesh::cuboid(DVec3::ZERO, DVec3::new(0.04, 0.04, 0.4));
        let arm = TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.36), DVec3::new(0.3, 0.04, 0.4));
        let offset = upright.positions.len() as u32;
        let mut positions = upright.positions.clone();
        positions.extend(arm.positions.iter().copied());
        let mut triangles = upright.triangles.clone();
        triangles.extend(arm.triangles.iter().map(|t| t.map(|i| i + offset)));
        let s = Scene::of_convex_parts(&[TriMesh::new(positions, triangles).expect("spout")], 2000);
        let points = s.points_of(&[0]);
        let collar = DVec3::new(0.02, 0.02, 0.0);
        let residual = spin_residual(&points, DVec3::Z, collar);
        assert!(residual > 0.06);
        assert!(off_round_spin(&s, &[0], &points, DVec3::Z, residual, 0.06).is_none());
    }
}
