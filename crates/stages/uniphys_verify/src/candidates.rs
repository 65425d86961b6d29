//! Articulation candidates of a moving part from its contact with its parent (reference 7.2 and
//! 17 item 13): 10 unit axes and 6 pivots.

use uniphys_geometry::{DQuat, DVec3, KdTree, fit_plane_ransac, kmeans, principal_axes};

use crate::patch::{PatchParams, grow_patch};
use crate::{VerifyError, VerifyResult};

/// Number of candidate axes.
pub const AXIS_CANDIDATES: usize = 10;
/// Number of candidate pivots.
pub const PIVOT_CANDIDATES: usize = 6;

/// Candidate axes and pivots of one moving part.
#[derive(Debug, Clone, PartialEq)]
pub struct ArticulationCandidates {
    /// Points of the parent near the moving group, object frame, metres.
    pub contact_points: Vec<DVec3>,
    /// Unit normal of the plane fitted to the contact points.
    pub contact_normal: DVec3,
    /// Ten unit axes: the contact normal, six in-plane directions 30 degrees apart starting at
    /// the contact's principal direction, then the three `frame_axes` given.
    pub axes: Vec<DVec3>,
    /// Six pivots: five k-means centres of the contact points, then their centroid.
    pub pivots: Vec<DVec3>,
}

/// Candidates for a moving group (points `moving_points`) attached to a parent (points
/// `parent_points`). `frame_axes` are the last three axis candidates: the world axes in the
/// reference; the moving part's principal axes make the candidates independent of the pose.
/// Deterministic for a given `seed`.
///
/// Errors: fewer than 3 contact points within 10 % of the diagonal.
pub fn articulation_candidates(
    moving_points: &[DVec3],
    parent_points: &[DVec3],
    frame_axes: [DVec3; 3],
    diagonal_m: f64,
    params: &PatchParams,
    seed: u64,
) -> VerifyResult<ArticulationCandidates> {
    let tree = KdTree::new(moving_points.to_vec());
    let start = params.start_fraction * diagonal_m;
    let step = params.step_fraction * diagonal_m;
    let (patch, _) = grow_patch(
        parent_points,
        &tree,
        start,
        step,
        params.initial_increments(),
        params.min_points.max(3),
    )
    .ok_or_else(|| {
        VerifyError::InvalidParameter(format!(
            "the part does not touch its parent: fewer than {} contact points within {:.3} m",
            params.min_points.max(3),
            params.max_initial_fraction * diagonal_m
        ))
    })?;
    let tolerance = 0.01 * diagonal_m;
    let (plane, _) = fit_plane_ransac(&patch, tolerance, 200, seed)?;
    let normal = plane.normal.normalize();
    let principal = principal_axes(&patch)
        .into_iter()
        .map(|a| a.reject_from_normalized(normal))
        .find(|a| a.length() > 1e-6)
        .unwrap_or_else(|| normal.any_orthonormal_vector())
        .normalize();
    let mut axes = vec![normal];
    for k in 0..6 {
        let turn = DQuat::from_axis_angle(normal, f64::from(k) * std::f64::consts::PI / 6.0);
        axes.push((turn * principal).normalize());
    }
    axes.extend(frame_axes.iter().map(|a| a.normalize()));
    let clusters = kmeans(&patch, 5, seed, 100)?;
    let mut pivots = clusters.centres;
    // Fewer distinct points than 5: repeat the first centre so the list keeps its length.
    while pivots.len() < PIVOT_CANDIDATES - 1 {
        pivots.push(pivots[0]);
    }
    pivots.push(patch.iter().sum::<DVec3>() / patch.len() as f64);
    Ok(ArticulationCandidates {
        contact_points: patch,
        contact_normal: normal,
        axes,
        pivots,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(z: f64, n: usize, step: f64) -> Vec<DVec3> {
        (0..n)
            .flat_map(|i| {
                (0..n).map(move |j| DVec3::new(i as f64 * step, j as f64 * step * 0.5, z))
            })
            .collect()
    }

    #[test]
    fn a_lid_on_a_box_gives_a_vertical_normal_and_in_plane_axes() {
        let lid = grid(0.01, 20, 0.05);
        let top = grid(0.0, 20, 0.05);
        let c = articulation_candidates(
            &lid,
            &top,
            [DVec3::X, DVec3::Y, DVec3::Z],
            1.5,
            &PatchParams::default(),
            1,
        )
        .expect("candidates");
        assert_eq!(c.axes.len(), AXIS_CANDIDATES);
        assert_eq!(c.pivots.len(), PIVOT_CANDIDATES);
        assert!((c.contact_normal.abs() - DVec3::Z).length() < 1e-9);
        for a in &c.axes {
            assert!((a.length() - 1.0).abs() < 1e-12);
        }
        for a in &c.axes[1..7] {
            assert!(a.dot(DVec3::Z).abs() < 1e-9);
        }
        // The contact spreads most along x (0.95 m against 0.475 m), so the first in-plane axis is x.
        assert!(
            (c.axes[1].abs() - DVec3::X).length() < 1e-6,
            "{:?}",
            c.axes[1]
        );
        assert!(
            (c.axes[4].abs() - DVec3::Y).length() < 1e-6,
            "{:?}",
            c.axes[4]
        );
        let centroid = top.iter().sum::<DVec3>() / top.len() as f64;
        assert!((c.pivots[5] - centroid).length() < 1e-12);
    }

    #[test]
    fn parts_that_do_not_touch_have_no_candidates() {
        let far = grid(1.0, 5, 0.05);
        let top = grid(0.0, 5, 0.05);
        let err = articulation_candidates(
            &far,
            &top,
            [DVec3::X, DVec3::Y, DVec3::Z],
            1.0,
            &PatchParams::default(),
            1,
        );
        assert!(err.is_err());
    }
}
