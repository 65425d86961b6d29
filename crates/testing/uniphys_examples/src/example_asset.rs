//! The ground-truth types: an example asset and the joints a correct pipeline should find.

use uniphys_geometry::MeshAsset;
use uniphys_types::JointKind;

/// A joint an analysis of the example should recover.
///
/// Axis and pivot are in the object frame (Z up, metres) at the pose the asset is built in.
#[derive(Debug, Clone, PartialEq)]
pub struct ExpectedJoint {
    /// Name of the part the joint moves.
    pub child: &'static str,
    /// Name of the part the joint is attached to.
    pub parent: &'static str,
    /// Joint kind; rigid attachments (handles, a screen) are [`JointKind::Fixed`].
    pub kind: JointKind,
    /// Unit axis; the sign matters: positive motion opens. `[0, 0, 1]` for fixed joints.
    pub axis: [f64; 3],
    /// A point on the axis (for fixed joints, a contact point), metres.
    pub pivot: [f64; 3],
    /// Lower and upper limit from the built pose, radians or metres; `(0, 0)` for fixed joints.
    pub limits: (f64, f64),
}

/// A procedurally built example with its ground truth.
#[derive(Debug, Clone, PartialEq)]
pub struct ExampleAsset {
    /// Short name, also the GLB file stem (`cabinet`).
    pub name: &'static str,
    /// One sentence saying what the object is and how it moves.
    pub description: &'static str,
    /// The asset in the service frame (Z up, metres), with `joints` filled from
    /// `expected_joints` (`PartId(i)` is `parts[i]`).
    pub asset: MeshAsset,
    /// The joints, movable and fixed, in the order of `asset.joints`.
    pub expected_joints: Vec<ExpectedJoint>,
}

impl ExampleAsset {
    /// Index of the part named `name`.
    #[must_use]
    pub fn part_index(&self, name: &str) -> Option<usize> {
        self.asset.parts.iter().position(|p| p.name == name)
    }
}
