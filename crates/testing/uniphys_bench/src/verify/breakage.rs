//! Deliberate breakages of a true joint, and whether a joint matches the truth.

use uniphys_geometry::DVec3;
use uniphys_types::{Joint, JointKind, JointLimits};

/// Pivot distance (in the object's [0,2] frame) within which a rotating joint is the truth.
pub(crate) const PIVOT_TOLERANCE_MODEL: f64 = 0.05;
/// Axis angle within which a joint is the truth, degrees.
pub(crate) const AXIS_TOLERANCE_DEG: f64 = 2.0;

/// How a true joint is broken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Breakage {
    /// The axis turned 90 degrees (towards the object axis least aligned with it).
    AxisTurned,
    /// The pivot moved across the part to the opposite edge (rotating joints).
    PivotOpposite,
    /// The range reversed: the part moves the other way (limited joints).
    Reversed,
    /// A prismatic joint made revolute about the same axis through the part's centre.
    PrismaticToRevolute,
    /// A revolute joint made prismatic along its axis.
    RevoluteToPrismatic,
}

impl Breakage {
    /// Every breakage, in table order.
    pub(crate) const ALL: [Self; 5] = [
        Self::AxisTurned,
        Self::PivotOpposite,
        Self::Reversed,
        Self::PrismaticToRevolute,
        Self::RevoluteToPrismatic,
    ];

    /// Short name for the command line.
    pub(crate) fn key(self) -> &'static str {
        match self {
            Self::AxisTurned => "axis",
            Self::PivotOpposite => "pivot",
            Self::Reversed => "reversed",
            Self::PrismaticToRevolute => "p2r",
            Self::RevoluteToPrismatic => "r2p",
        }
    }

    /// Name for tables.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::AxisTurned => "axis turned 90 deg",
            Self::PivotOpposite => "pivot to the opposite edge",
            Self::Reversed => "direction reversed",
            Self::PrismaticToRevolute => "prismatic made revolute",
            Self::RevoluteToPrismatic => "revolute made prismatic",
        }
    }

    /// The broken joint, or `None` when the breakage does not apply or leaves the joint right
    /// (a knob's pivot moved across a knob centred on its axis is still on the axis).
    pub(crate) fn apply(self, truth: &Joint, child_points: &[DVec3], scale: f64) -> Option<Joint> {
        let axis = DVec3::from_array(truth.axis_in_object).normalize();
        let pivot = DVec3::from_array(truth.pivot_in_object_m);
        let centre = child_points.iter().sum::<DVec3>() / child_points.len().max(1) as f64;
        let mut broken = truth.clone();
        match self {
            Self::AxisTurned => {
                let least = [DVec3::X, DVec3::Y, DVec3::Z]
                    .into_iter()
                    .min_by(|a, b| a.dot(axis).abs().total_cmp(&b.dot(axis).abs()))
                    .unwrap_or(DVec3::X);
                broken.axis_in_object = least.reject_from_normalized(axis).normalize().to_array();
            }
            Self::PivotOpposite => {
                if !rotating(truth.kind) {
                    return None;
                }
                let offset = (pivot - centre).reject_from_normalized(axis);
                broken.pivot_in_object_m = (pivot - 2.0 * offset).to_array();
            }
            Self::Reversed => {
                let l = truth.limits?;
                broken.limits = Some(JointLimits {
                    lower: -l.upper,
                    upper: -l.lower,
                });
            }
            Self::PrismaticToRevolute => {
                if truth.kind != JointKind::Prismatic {
                    return None;
                }
                broken.kind = JointKind::Revolute;
                broken.pivot_in_object_m = centre.to_array();
                broken.limits = Some(JointLimits {
                    lower: 0.0,
                    upper: std::f64::consts::FRAC_PI_2,
                });
            }
            Self::RevoluteToPrismatic => {
                if truth.kind != JointKind::Revolute {
                    return None;
                }
                let (lo, hi) = child_points
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                        let t = p.dot(axis);
                        (lo.min(t), hi.max(t))
                    });
                broken.kind = JointKind::Prismatic;
                broken.limits = Some(JointLimits {
                    lower: 0.0,
                    upper: (0.5 * (hi - lo)).max(1e-3),
                });
            }
        }
        (!same_motion(&broken, truth, scale, RangeAgreement::HalfIou)).then_some(broken)
    }
}

/// Revolute and continuous joints turn.
pub(crate) fn rotating(kind: JointKind) -> bool {
    matches!(kind, JointKind::Revolute | JointKind::Continuous)
}

/// Angle between two lines (sign ignored), degrees.
pub(crate) fn line_angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .abs()
        .clamp(0.0, 1.0)
        .acos()
        .to_degrees()
}

/// Distance from `point` to the line through `on` along `axis`.
pub(crate) fn distance_to_line(point: DVec3, on: DVec3, axis: DVec3) -> f64 {
    (point - on)
        .reject_from_normalized(axis.normalize())
        .length()
}

/// How closely a range must agree with the true one for a joint to be the truth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RangeAgreement {
    /// The part moves the way the truth moves it: at least half of the range lies in the true
    /// range (a hinge made a slide and turned back cannot know how far the truth turns).
    SameWay,
    /// The signed ranges' intersection over union is at least one half.
    HalfIou,
}

/// Whether `pred` moves the part as `truth` does: same kind of motion (turning or sliding), axis
/// within 2 degrees, pivot on the true axis line within 0.05 of the [0,2] frame (`scale`: model
/// units per metre), and ranges that agree as `agreement` asks.
pub(crate) fn same_motion(
    pred: &Joint,
    truth: &Joint,
    scale: f64,
    agreement: RangeAgreement,
) -> bool {
    if rotating(pred.kind) != rotating(truth.kind) {
        return false;
    }
    let (pa, ta) = (
        DVec3::from_array(pred.axis_in_object).normalize(),
        DVec3::from_array(truth.axis_in_object).normalize(),
    );
    if line_angle_deg(pa, ta) > AXIS_TOLERANCE_DEG {
        return false;
    }
    if rotating(truth.kind) {
        let d = distance_to_line(
            DVec3::from_array(pred.pivot_in_object_m),
            DVec3::from_array(truth.pivot_in_object_m),
            ta,
        );
        if d * scale > PIVOT_TOLERANCE_MODEL {
            return false;
        }
    }
    match (truth.kind, pred.limits, truth.limits) {
        (JointKind::Continuous, _, _) | (_, None, _) | (_, _, None) => true,
        (_, Some(p), Some(t)) => {
            let (lo, hi) = if pa.dot(ta) >= 0.0 {
                (p.lower, p.upper)
            } else {
                (-p.upper, -p.lower)
            };
            match agreement {
                RangeAgreement::HalfIou => interval_iou((lo, hi), (t.lower, t.upper)) >= 0.5,
                RangeAgreement::SameWay => {
                    let inside = (hi.min(t.upper) - lo.max(t.lower)).max(0.0);
                    inside >= 0.5 * (hi - lo).max(1e-12)
                }
            }
        }
    }
}

fn interval_iou(a: (f64, f64), b: (f64, f64)) -> f64 {
    let inter = (a.1.min(b.1) - a.0.max(b.0)).max(0.0);
    let union = (a.1.max(b.1) - a.0.min(b.0)).max(1e-12);
    inter / union
}
