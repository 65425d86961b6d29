//! Whether a part's shape fits the way it turns: a part turns about an axis through its middle
//! only when it is round about that axis (a knob, a wheel, a cap), and a thin panel turns about
//! an axis in its own plane (a door's hinge edge, a lid's back edge), never about its normal
//! unless it is round. Collision alone cannot tell these apart: a door spinning in front of its
//! cabinet, or a lid turning about its centre line above the box, hits nothing.

use uniphys_geometry::{DQuat, DVec3, KdTree, box_axes, projection_range};

use crate::motion::JointMotion;

/// Points of the part used for the roundness test.
const ROUND_SAMPLES: usize = 400;
/// Turns the part is compared with itself after.
const ROUND_TURNS_RAD: [f64; 3] = [
    std::f64::consts::FRAC_PI_3,
    2.0 * std::f64::consts::FRAC_PI_3,
    std::f64::consts::PI,
];

/// How a turning part sits on its axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnFit {
    /// Distance from the axis line to the part's centroid over the part's largest distance from
    /// the line (0: the axis runs through its middle; near 1: along its edge).
    pub offcentre_ratio: f64,
    /// Thickness over largest extent of the part's tight box.
    pub thinness: f64,
    /// Angle between the axis and the thin direction of the part's box, radians.
    pub axis_to_thin_rad: f64,
    /// Largest over a few turns about the axis of the mean distance from the turned points to
    /// the part at rest, over the part's largest extent (0: round about the axis).
    pub roundness_error: f64,
    /// Spacing of the surface samples over the part's largest extent: the mismatch sampling
    /// alone leaves.
    pub sampling_noise: f64,
}

impl TurnFit {
    /// Measures `part_points` (the turning part alone, samples `spacing_m` apart on its
    /// surface) against the axis of `motion`.
    pub(crate) fn of(part_points: &[DVec3], spacing_m: f64, motion: &JointMotion) -> Option<Self> {
        if part_points.len() < 4 {
            return None;
        }
        let axis = motion.axis_in_object;
        let pivot = motion.pivot_in_object_m;
        let off_axis = |p: DVec3| (p - pivot).reject_from_normalized(axis);
        let centroid = part_points.iter().sum::<DVec3>() / part_points.len() as f64;
        let reach = part_points
            .iter()
            .map(|p| off_axis(*p).length())
            .fold(0.0, f64::max);
        let axes = box_axes(part_points);
        let extents = axes.map(|a| {
            let (lo, hi) = projection_range(part_points, a);
            hi - lo
        });
        let (mut thin, mut largest) = (0, 0);
        for k in 1..3 {
            if extents[k] < extents[thin] {
                thin = k;
            }
            if extents[k] > extents[largest] {
                largest = k;
            }
        }
        let size = extents[largest].max(1e-12);
        let stride = (part_points.len() / ROUND_SAMPLES).max(1);
        let sample: Vec<DVec3> = part_points.iter().step_by(stride).copied().collect();
        let tree = KdTree::new(part_points.to_vec());
        let roundness_error = ROUND_TURNS_RAD
            .iter()
            .map(|&angle| {
                let turn = DQuat::from_axis_angle(axis, angle);
                sample
                    .iter()
                    .map(|p| tree.nearest_distance(pivot + turn * (*p - pivot)))
                    .sum::<f64>()
                    / sample.len() as f64
                    / size
            })
            .fold(0.0, f64::max);
        Some(Self {
            offcentre_ratio: if reach > 0.0 {
                off_axis(centroid).length() / reach
            } else {
                0.0
            },
            thinness: extents[thin] / size,
            axis_to_thin_rad: axis.dot(axes[thin]).abs().clamp(0.0, 1.0).acos(),
            roundness_error,
            sampling_noise: spacing_m / size,
        })
    }

    /// Round about the axis: it maps onto itself when turned, within `roundness_max` of its
    /// size beyond the sampling's own mismatch.
    pub fn round(&self, roundness_max: f64) -> bool {
        self.roundness_error <= roundness_max + self.sampling_noise
    }
}
