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
#[derive(Debug, Clone, PartialEq)]
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
