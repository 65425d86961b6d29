//! One side of an evaluation pair (a prediction or a ground truth), whatever it was loaded from:
//! parts by name, joints by child part name, object values, and the object's bounds.

use uniphys_geometry::{Aabb, DVec3};
use uniphys_uniphysgen::CoordinateFrame;

use crate::{ObjectValues, PhysicalProperties};

/// One part: its name and, when the source has them, its physical properties.
///
/// Units on both sides of a pair are the dataset's: density g/cm^3, Young's modulus GPa,
/// hardness HV (ALDE does not depend on them as long as both sides agree).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AnnotatedPart {
    /// Part name, the key of matching.
    pub name: String,
    /// Physical properties, `None` when the source has none (a URDF).
    pub physics: Option<PhysicalProperties>,
}

/// One joint, keyed by the name of the part it moves.
#[derive(Debug, Clone, PartialEq)]
pub struct AnnotatedJoint {
    /// Name of the child part (the part the joint moves).
    pub child: String,
    /// Dataset movement type: `B` prismatic, `C` revolute or continuous, `D` fixed.
    pub motion_type: char,
    /// Axis direction in the source's object frame (any length, any sign).
    pub axis: [f64; 3],
    /// Pivot in the source's object frame, in the source's length unit; `None` if not given.
    pub pivot_in_object: Option<[f64; 3]>,
    /// Range: radians for `C` (continuous joints `[0, 2 pi]`, as the dataset record writes them),
    /// the source's length unit for `B`; `None` if the source gives none.
    pub range: Option<[f64; 2]>,
    /// The motion-coupled group by part name: the child and every part that moves rigidly with
    /// it, sorted.
    pub members: Vec<String>,
}

impl AnnotatedJoint {
    /// Whether the joint has a degree of freedom (`B` or `C`).
    #[must_use]
    pub fn is_movable(&self) -> bool {
        matches!(self.motion_type, 'B' | 'C')
    }
}

/// One side of an evaluation pair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AnnotatedAsset {
    /// Where it was loaded from, for messages and reports.
    pub origin: String,
    /// Bounds of the whole object in its object frame (`[min, max]`, source length unit);
    /// `None` when unknown (no pivot error or prismatic limit IoU then).
    pub bounds_in_object: Option<[[f64; 3]; 2]>,
    /// Parts, in source order.
    pub parts: Vec<AnnotatedPart>,
    /// Joints, movable and fixed, in source order.
    pub joints: Vec<AnnotatedJoint>,
    /// Object-level values (dimensions in metres, mass in kg), when the source has them.
    pub object: Option<ObjectValues>,
}

impl AnnotatedAsset {
    /// The `[0, 2]` model frame of the object (reference 14.3, object AABB only), if its bounds
    /// are known.
    #[must_use]
    pub fn model_frame(&self) -> Option<CoordinateFrame> {
        let [min, max] = self.bounds_in_object?;
        let bounds = Aabb {
            min: DVec3::from_array(min),
            max: DVec3::from_array(max),
        };
        Some(CoordinateFrame::from_object_bounds(bounds))
    }

    /// The joint moving the part called `child`, if any.
    #[must_use]
    pub fn joint_of(&self, child: &str) -> Option<&AnnotatedJoint> {
        self.joints.iter().find(|j| j.child == child)
    }

    /// The part called `name`, if any.
    #[must_use]
    pub fn part(&self, name: &str) -> Option<&AnnotatedPart> {
        self.parts.iter().find(|p| p.name == name)
    }
}

/// Sorted, de-duplicated member names.
pub(crate) fn sorted_members(names: impl IntoIterator<Item = String>) -> Vec<String> {
    let mut v: Vec<String> = names.into_iter().collect();
    v.sort();
    v.dedup();
    v
}

/// `acc` grown to contain the box `[lo, hi]`.
pub(crate) fn union_bounds(
    acc: Option<[[f64; 3]; 2]>,
    lo: [f64; 3],
    hi: [f64; 3],
) -> Option<[[f64; 3]; 2]> {
    Some(match acc {
        None => [lo, hi],
        Some([a, b]) => [
            [a[0].min(lo[0]), a[1].min(lo[1]), a[2].min(lo[2])],
            [b[0].max(hi[0]), b[1].max(hi[1]), b[2].max(hi[2])],
        ],
    })
}
