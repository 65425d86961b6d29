//! Builds an [`ExampleAsset`]: parts made of closed shells with one named material each, and the
//! expected joints, converted to [`Joint`] values for [`MeshAsset::joints`].

use uniphys_geometry::{DVec3, MeshAsset, MeshPart, TriMesh};
use uniphys_types::{Joint, JointKind, JointLimits, PartId, Provenance};

use crate::materials::NamedMaterial;
use crate::{ExampleAsset, ExpectedJoint};

/// Provenance detail of the joints of every example.
pub(crate) const JOINT_PROVENANCE: &str = "example generator";

/// An example under construction.
#[derive(Debug, Default)]
pub(crate) struct Assembly {
    asset: MeshAsset,
    joints: Vec<ExpectedJoint>,
}

impl Assembly {
    /// Adds a part named `name` made of the given closed shells, all of `material`.
    pub fn part(&mut self, name: &str, material: NamedMaterial, shells: &[TriMesh]) {
        let index = self.material_index(material);
        let mut mesh = TriMesh::merge(shells);
        mesh.face_materials = Some(vec![index; mesh.triangles.len()]);
        self.asset.parts.push(MeshPart {
            name: name.to_owned(),
            mesh,
        });
    }

    /// Adds an expected joint.
    pub fn joint(&mut self, joint: ExpectedJoint) {
        self.joints.push(joint);
    }

    /// Adds a fixed attachment of `child` to `parent` touching at `contact`.
    pub fn fixed(&mut self, child: &'static str, parent: &'static str, contact: [f64; 3]) {
        self.joint(ExpectedJoint {
            child,
            parent,
            kind: JointKind::Fixed,
            axis: [0.0, 0.0, 1.0],
            pivot: contact,
            limits: (0.0, 0.0),
        });
    }

    /// The finished example, moved so that it rests on z = 0 with its bounds centred on x/y;
    /// joints whose part names do not resolve are left out of `asset.joints` (the catalogue
    /// tests check that none are).
    pub fn finish(mut self, name: &'static str, description: &'static str) -> ExampleAsset {
        self.rest_centred();
        let joints: Vec<Joint> = self
            .joints
            .iter()
            .filter_map(|j| self.to_joint(j))
            .collect();
        self.asset.joints = joints;
        ExampleAsset {
            name,
            description,
            asset: self.asset,
            expected_joints: self.joints,
        }
    }

    /// Translates parts and pivots so that the bounds' centre has x = y = 0 and min z = 0.
    fn rest_centred(&mut self) {
        let bounds = self.asset.bounds();
        if bounds.is_empty() {
            return;
        }
        let centre = bounds.center();
        let shift = -DVec3::new(centre.x, centre.y, bounds.min.z);
        for part in &mut self.asset.parts {
            for p in &mut part.mesh.positions {
                *p += shift;
            }
        }
        for joint in &mut self.joints {
            joint.pivot = (DVec3::from_array(joint.pivot) + shift).to_array();
        }
    }

    fn material_index(&mut self, material: NamedMaterial) -> u32 {
        let materials = &mut self.asset.materials;
        let index = materials
            .iter()
            .position(|m| m.name == material.name)
            .unwrap_or_else(|| {
                materials.push(material.surface());
                materials.len() - 1
            });
        part_id(index).0
    }

    fn part_index(&self, name: &str) -> Option<usize> {
        self.asset.parts.iter().position(|p| p.name == name)
    }

    fn to_joint(&self, j: &ExpectedJoint) -> Option<Joint> {
        let child = part_id(self.part_index(j.child)?);
        let parent = part_id(self.part_index(j.parent)?);
        let coupled_parts = if j.kind.is_movable() {
            self.fixed_descendants(j.child)
        } else {
            Vec::new()
        };
        Some(Joint {
            name: format!("{}_to_{}", j.parent, j.child),
            kind: j.kind,
            parent,
            child,
            axis_in_object: j.axis,
            pivot_in_object_m: j.pivot,
            limits: j.kind.needs_limits().then_some(JointLimits {
                lower: j.limits.0,
                upper: j.limits.1,
            }),
            damping: 0.0,
            friction: 0.0,
            coupled_parts,
            provenance: Provenance::input(JOINT_PROVENANCE),
        })
    }

    /// Parts rigidly attached to `name` through chains of fixed joints, sorted.
    fn fixed_descendants(&self, name: &str) -> Vec<PartId> {
        let mut found: Vec<&str> = Vec::new();
        let mut frontier = vec![name];
        while let Some(parent) = frontier.pop() {
            for j in &self.joints {
                if j.kind == JointKind::Fixed && j.parent == parent && !found.contains(&j.child) {
                    found.push(j.child);
                    frontier.push(j.child);
                }
            }
        }
        let mut ids: Vec<PartId> = found
            .iter()
            .filter_map(|n| self.part_index(n).map(part_id))
            .collect();
        ids.sort_unstable();
        ids
    }
}

fn part_id(index: usize) -> PartId {
    PartId(u32::try_from(index).unwrap_or(u32::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::materials::{METAL_STEEL, WOOD_OAK};
    use crate::shapes::cuboid;

    #[test]
    fn joints_get_part_ids_limits_and_coupled_fixed_children() {
        let mut a = Assembly::default();
        let shell = cuboid(DVec3::ZERO, DVec3::ONE);
        a.part("body", WOOD_OAK, &[cuboid(-DVec3::ONE, DVec3::ONE)]);
        a.part("drawer", WOOD_OAK, std::slice::from_ref(&shell));
        a.part("handle", METAL_STEEL, &[shell]);
        a.joint(ExpectedJoint {
            child: "drawer",
            parent: "body",
            kind: JointKind::Prismatic,
            axis: [0.0, -1.0, 0.0],
            pivot: [0.0; 3],
            limits: (0.0, 0.3),
        });
        a.fixed("handle", "drawer", [0.0; 3]);
        let example = a.finish("t", "test");
        assert_eq!(example.asset.bounds().min, DVec3::new(-1.0, -1.0, 0.0));
        assert_eq!(example.expected_joints[0].pivot, [0.0, 0.0, 1.0]);
        assert_eq!(example.asset.materials.len(), 2);
        assert_eq!(
            example.asset.parts[2].mesh.face_materials,
            Some(vec![1; 12])
        );
        let joints = &example.asset.joints;
        assert_eq!(joints.len(), 2);
        assert_eq!((joints[0].parent, joints[0].child), (PartId(0), PartId(1)));
        assert_eq!(joints[0].coupled_parts, vec![PartId(2)]);
        assert_eq!(joints[0].limits.map(|l| l.upper), Some(0.3));
        assert_eq!(joints[1].limits, None);
        assert_eq!(joints[1].provenance, Provenance::input("example generator"));
    }
}
