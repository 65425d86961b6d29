//! A general, deterministic writer from [`MeshAsset`] to binary glTF 2.0 (GLB).
//!
//! Layout: one scene; one node and one mesh per part (both named after the part, in part order);
//! one primitive per material the part uses, in ascending material order, holding the part's
//! triangles of that material in their original order. Each primitive has `POSITION` (with
//! `min`/`max`), flat per-face `NORMAL` (a vertex is duplicated where its faces' normals differ),
//! `TEXCOORD_0` and `COLOR_0` when the mesh has them, and `u32` indices. Materials keep their
//! index, name and base colour factor; parts without face materials use an extra material named
//! `default`. Every attribute and index array has its own buffer view in the single buffer.

use std::collections::hash_map::Entry;
use std::collections::{BTreeMap, HashMap};

use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::{USize64, Validate};
use uniphys_geometry::{DVec3, MeshAsset, MeshPart, SurfaceMaterial, TriMesh};

use crate::ExamplesError;
use crate::glb_container::{pack_glb, to_u32};

/// The up axis of the written file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GlbFrame {
    /// Coordinates as in the service frame (Z up), unchanged.
    ZUp,
    /// glTF's own convention (Y up): `(x, y, z)` is written as `(x, z, -y)`, the inverse of the
    /// ingest rotation `(x, y, z) -> (x, -z, y)`.
    YUp,
}

impl GlbFrame {
    /// Maps a point or direction from the service frame (Z up) to this frame.
    #[must_use]
    pub fn map(self, v: DVec3) -> DVec3 {
        match self {
            Self::ZUp => v,
            Self::YUp => DVec3::new(v.x, v.z, -v.y),
        }
    }
}

/// Name of the material given to parts that have no face materials.
pub const DEFAULT_MATERIAL_NAME: &str = "default";

const DEFAULT_MATERIAL_RGBA: [f32; 4] = [0.8, 0.8, 0.8, 1.0];

/// Writes `asset` as GLB bytes, with coordinates in the frame `up`.
///
/// Materials are written with `pbrMetallicRoughness.baseColorFactor` from
/// [`SurfaceMaterial::base_color_rgba`], metallic 0 and roughness 0.5 (the asset carries no such
/// values), and alpha mode `BLEND` when alpha is below 1. Textures are not written: UVs are kept
/// as `TEXCOORD_0` but [`SurfaceMaterial::base_color_texture`] and [`MeshAsset::textures`] are
/// ignored. Joints are not written either (glTF has none). The output depends only on the input:
/// the same asset always gives the same bytes.
///
/// # Errors
/// [`ExamplesError::MaterialOutOfRange`] if a face material index has no material,
/// [`ExamplesError::TooLarge`] if a size exceeds `u32`, and [`ExamplesError::InvalidGltf`] or
/// [`ExamplesError::Json`] if the document cannot be produced (a bug).
pub fn write_glb(asset: &MeshAsset, up: GlbFrame) -> Result<Vec<u8>, ExamplesError> {
    let mut writer = Writer::default();
    for material in &asset.materials {
        writer.root.push(material_json(material));
    }
    let needs_default = asset
        .parts
        .iter()
        .any(|p| !p.mesh.triangles.is_empty() && p.mesh.face_materials.is_none());
    let default_material = u32::try_from(asset.materials.len())
        .map_err(|_| ExamplesError::TooLarge { what: "materials" })?;
    if needs_default {
        writer.root.push(material_json(&SurfaceMaterial {
            name: DEFAULT_MATERIAL_NAME.to_owned(),
            base_color_rgba: DEFAULT_MATERIAL_RGBA,
            base_color_texture: None,
        }));
    }
    let mut nodes = Vec::with_capacity(asset.parts.len());
    for part in &asset.parts {
        let groups = material_groups(part, default_material, asset.materials.len())?;
        let mut primitives = Vec::with_capacity(groups.len());
        for (material, faces) in groups {
            primitives.push(writer.primitive(&part.mesh, &faces, material, up)?);
        }
        let mesh = (!primitives.is_empty()).then(|| {
            writer.root.push(json::Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(part.name.clone()),
                primitives,
                weights: None,
            })
        });
        nodes.push(writer.root.push(json::Node {
            mesh,
            name: Some(part.name.clone()),
            ..Default::default()
        }));
    }
    let scene = writer.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes,
    });
    writer.root.scene = Some(scene);
    writer.finish()
}

/// The part's triangles grouped by material, in ascending material order.
fn material_groups(
    part: &MeshPart,
    default_material: u32,
    material_count: usize,
) -> Result<BTreeMap<u32, Vec<usize>>, ExamplesError> {
    let mut groups: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for triangle in 0..part.mesh.triangles.len() {
        let material = match &part.mesh.face_materials {
            Some(materials) => {
                let material = materials[triangle];
                if material as usize >= material_count {
                    return Err(ExamplesError::MaterialOutOfRange {
                        part: part.name.clone(),
                        triangle,
                        material,
                        count: material_count,
                    });
                }
                material
            }
            None => default_material,
        };
        groups.entry(material).or_default().push(triangle);
    }
    Ok(groups)
}

fn material_json(material: &SurfaceMaterial) -> json::Material {
    let rgba = material.base_color_rgba;
    json::Material {
        name: (!material.name.is_empty()).then(|| material.name.clone()),
        alpha_mode: Valid(if rgba[3] < 1.0 {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(rgba),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.5),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Vertex attributes of one primitive, each vertex unique by (source vertex, face normal).
#[derive(Default)]
struct PrimitiveData {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    uvs: Vec<[f32; 2]>,
    colors: Vec<[f32; 4]>,
    indices: Vec<u32>,
}

impl PrimitiveData {
    fn build(mesh: &TriMesh, faces: &[usize], up: GlbFrame) -> Result<Self, ExamplesError> {
        let mut data = Self::default();
        let mut index_of: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
        let fallback_normal = up.map(DVec3::Z);
        for &face in faces {
            let mut normal = up.map(mesh.face_normal(face));
            if normal == DVec3::ZERO {
                normal = fallback_normal;
            }
            let normal = normal.as_vec3().to_array();
            for vertex in mesh.triangles[face] {
                let key = (vertex, normal.map(f32::to_bits));
                let index = match index_of.entry(key) {
                    Entry::Occupied(entry) => *entry.get(),
                    Entry::Vacant(entry) => {
                        let index = to_u32(data.positions.len(), "vertex count")?;
                        let v = vertex as usize;
                        data.positions
                            .push(up.map(mesh.positions[v]).as_vec3().to_array());
                        data.normals.push(normal);
                        if let Some(uvs) = &mesh.uvs {
                            data.uvs.push(uvs[v]);
                        }
                        if let Some(colors) = &mesh.vertex_colors {
                            data.colors.push(colors[v]);
                        }
                        *entry.insert(index)
                    }
                };
                data.indices.push(index);
            }
        }
        Ok(data)
    }
}

#[derive(Default)]
struct Writer {
    root: json::Root,
    bin: Vec<u8>,
}

impl Writer {
    fn primitive(
        &mut self,
        mesh: &TriMesh,
        faces: &[usize],
        material: u32,
        up: GlbFrame,
    ) -> Result<json::mesh::Primitive, ExamplesError> {
        use json::accessor::{ComponentType, Type};
        use json::buffer::Target;
        use json::mesh::Semantic;

        let data = PrimitiveData::build(mesh, faces, up)?;
        let (min, max) = bounds(&data.positions);
        let mut attributes = BTreeMap::new();
        let count = data.positions.len();
        let position = self.accessor(
            &flat(&data.positions),
            count,
            Type::Vec3,
            ComponentType::F32,
            Some((min.to_vec(), max.to_vec())),
            Target::ArrayBuffer,
        )?;
        attributes.insert(Valid(Semantic::Positions), position);
        let normal = self.accessor(
            &flat(&data.normals),
            count,
            Type::Vec3,
            ComponentType::F32,
            None,
            Target::ArrayBuffer,
        )?;
        attributes.insert(Valid(Semantic::Normals), normal);
        if mesh.uvs.is_some() {
            let uv = self.accessor(
                &flat(&data.uvs),
                count,
                Type::Vec2,
                ComponentType::F32,
                None,
                Target::ArrayBuffer,
            )?;
            attributes.insert(Valid(Semantic::TexCoords(0)), uv);
        }
        if mesh.vertex_colors.is_some() {
            let color = self.accessor(
                &flat(&data.colors),
                count,
                Type::Vec4,
                ComponentType::F32,
                None,
                Target::ArrayBuffer,
            )?;
            attributes.insert(Valid(Semantic::Colors(0)), color);
        }
        let index_bytes: Vec<u8> = data.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices = self.accessor(
            &index_bytes,
            data.indices.len(),
            Type::Scalar,
            ComponentType::U32,
            None,
            Target::ElementArrayBuffer,
        )?;
        Ok(json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: Some(json::Index::new(material)),
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        })
    }

    /// Appends `bytes` (a multiple of four long) as a new buffer view with an accessor over it.
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        type_: json::accessor::Type,
        component: json::accessor::ComponentType,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
        target: json::buffer::Target,
    ) -> Result<json::Index<json::Accessor>, ExamplesError> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        to_u32(self.bin.len(), "binary buffer")?;
        let view = self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: Default::default(),
        });
        let (min, max) = match min_max {
            Some((min, max)) => (Some(json::Value::from(min)), Some(json::Value::from(max))),
            None => (None, None),
        };
        Ok(self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        }))
    }

    fn finish(mut self) -> Result<Vec<u8>, ExamplesError> {
        self.root.asset.generator = Some("uniphys_examples".to_owned());
        if !self.bin.is_empty() {
            self.root.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
        }
        let mut problems = Vec::new();
        self.root
            .validate(&self.root, json::Path::new, &mut |path, error| {
                problems.push(format!("{}: {error}", path()));
            });
        if !problems.is_empty() {
            return Err(ExamplesError::InvalidGltf(problems.join("; ")));
        }
        let json = self.root.to_vec()?;
        pack_glb(&json, &self.bin)
    }
}

fn flat<const N: usize>(values: &[[f32; N]]) -> Vec<u8> {
    values
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect()
}

fn bounds(positions: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in positions {
        for axis in 0..3 {
            min[axis] = min[axis].min(p[axis]);
            max[axis] = max[axis].max(p[axis]);
        }
    }
    (min, max)
}
