use glam::{DMat4, DVec3};
use uniphys_types::Joint;

use crate::{Aabb, TriMesh};

/// A texture image, decoded to 8-bit RGBA (sRGB as stored in the file).
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// Name or file name of the image, for messages.
    pub name: String,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGBA bytes, `width * height * 4` of them.
    pub rgba8: Vec<u8>,
}

/// The visual material of a surface, as far as the pipeline uses it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SurfaceMaterial {
    /// Material name from the input (`""` if it had none).
    pub name: String,
    /// Base colour factor, linear RGBA in [0, 1].
    pub base_color_rgba: [f32; 4],
    /// Index into [`MeshAsset::textures`] of the base colour texture, if any.
    pub base_color_texture: Option<usize>,
}

/// One part of an input asset: a name and its mesh in the object frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshPart {
    /// Name from the input (glTF node, OBJ group, URDF link) or assigned (`part_0`).
    pub name: String,
    /// The part's mesh in the object frame.
    pub mesh: TriMesh,
}

/// An ingested asset: its parts in the object frame (Z up, metres), their materials and textures,
/// and the joints the input declared (empty unless the input was articulated).
///
/// Joints refer to parts by position: `PartId(i)` is `parts[i]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshAsset {
    /// Parts, in input order.
    pub parts: Vec<MeshPart>,
    /// Materials referenced by the parts' face material indices.
    pub materials: Vec<SurfaceMaterial>,
    /// Textures referenced by the materials.
    pub textures: Vec<Texture>,
    /// Joints declared by the input, in the object frame.
    pub joints: Vec<Joint>,
}

impl MeshAsset {
    /// Bounds of all parts.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.parts
            .iter()
            .fold(Aabb::EMPTY, |b, p| b.union(p.mesh.bounds()))
    }

    /// Total number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.parts.iter().map(|p| p.mesh.triangle_count()).sum()
    }

    /// All parts merged into one mesh (the "single mesh" view of the asset).
    #[must_use]
    pub fn merged(&self) -> TriMesh {
        TriMesh::merge(self.parts.iter().map(|p| &p.mesh))
    }

    /// Moves the asset so it rests on z = 0, centred in x and y (the service's object frame);
    /// returns the translation applied.
    pub fn rest_on_ground(&mut self) -> DVec3 {
        let b = self.bounds();
        let c = b.center();
        let offset = DVec3::new(-c.x, -c.y, -b.min.z);
        self.transform(&DMat4::from_translation(offset));
        offset
    }

    /// Applies a similarity transform (rotation, uniform scale, translation) to every part and
    /// to the joints' axes and pivots.
    pub fn transform(&mut self, m: &DMat4) {
        for part in &mut self.parts {
            part.mesh = part.mesh.transformed(m);
        }
        for joint in &mut self.joints {
            let axis = m
                .transform_vector3(DVec3::from_array(joint.axis_in_object))
                .normalize_or_zero();
            joint.axis_in_object = axis.to_array();
            joint.pivot_in_object_m = m
                .transform_point3(DVec3::from_array(joint.pivot_in_object_m))
                .to_array();
            if joint.kind == uniphys_types::JointKind::Prismatic {
                let scale = m.transform_vector3(DVec3::X).length();
                if let Some(limits) = &mut joint.limits {
                    limits.lower *= scale;
                    limits.upper *= scale;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use uniphys_types::{JointKind, JointLimits, PartId, Provenance};

    use super::*;

    #[test]
    fn resting_on_the_ground_moves_parts_and_joint_pivots_together() {
        let mut asset = MeshAsset {
            parts: vec![MeshPart {
                name: "block".into(),
                mesh: TriMesh::cuboid(DVec3::new(1.0, 2.0, 3.0), DVec3::new(3.0, 4.0, 5.0)),
            }],
            joints: vec![Joint {
                name: "j".into(),
                kind: JointKind::Prismatic,
                parent: PartId(0),
                child: PartId(0),
                axis_in_object: [1.0, 0.0, 0.0],
                pivot_in_object_m: [2.0, 3.0, 4.0],
                limits: Some(JointLimits {
                    lower: 0.0,
                    upper: 0.5,
                }),
                damping: 0.0,
                friction: 0.0,
                coupled_parts: vec![],
                provenance: Provenance::rule("test"),
            }],
            ..MeshAsset::default()
        };
        let offset = asset.rest_on_ground();
        assert_eq!(offset, DVec3::new(-2.0, -3.0, -3.0));
        let b = asset.bounds();
        assert_eq!(
            (b.min, b.max),
            (DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, 1.0, 2.0))
        );
        assert_eq!(asset.joints[0].pivot_in_object_m, [0.0, 0.0, 1.0]);
        assert_eq!(
            asset.joints[0].limits,
            Some(JointLimits {
                lower: 0.0,
                upper: 0.5
            })
        );
    }
}
