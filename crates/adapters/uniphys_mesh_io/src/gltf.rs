//! glTF 2.0 (`.gltf` with embedded or external data, and `.glb`): one part per node that has a
//! mesh, in depth-first scene order, placed by the node's world transform; all triangle
//! primitives of the mesh merged with per-face materials; points and lines skipped.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use ::gltf::mesh::Mode;
use ::gltf::{Document, Gltf, Node, Semantic};
use uniphys_geometry::{DMat4, DVec3, MeshAsset, MeshPart, SurfaceMaterial, TriMesh};

use crate::gltf_data::{check_glb_header, load_buffers, load_uri, read_floats, read_indices};
use crate::guard::guarded;
use crate::source::Session;
use crate::texture::decode_texture;
use crate::{IngestError, IngestResult};

/// Required extensions that do not change how geometry or base colours are read.
const HARMLESS_EXTENSIONS: &[&str] = &[
    "KHR_mesh_quantization",
    "KHR_materials_unlit",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_variants",
    "KHR_lights_punctual",
];

/// Reads a `.gltf` or `.glb` file (at canonical `path`).
pub(crate) fn read_gltf(
    path: &Path,
    bytes: &[u8],
    session: &mut Session<'_>,
) -> IngestResult<MeshAsset> {
    let format = if bytes.starts_with(b"glTF") {
        "glb"
    } else {
        "gltf"
    };
    if format == "glb" {
        check_glb_header(path, bytes)?;
    }
    let parse_err = |e: ::gltf::Error| IngestError::parse(path, format, e.to_string());
    let Gltf { document, blob } =
        guarded(path, format, || Gltf::from_slice_without_validation(bytes))?.map_err(parse_err)?;
    if let Some(ext) = document
        .extensions_required()
        .find(|e| !HARMLESS_EXTENSIONS.contains(e))
    {
        return Err(IngestError::Unsupported {
            path: path.to_path_buf(),
            what: format!("the required glTF extension {ext}"),
        });
    }
    let document =
        guarded(path, format, || Document::from_json(document.into_json()))?.map_err(parse_err)?;
    // The gltf crate's accessors unwrap a few values that validation does not cover; a panic
    // there becomes a parse error too.
    guarded(path, format, || {
        build(&document, blob, path, format, session)
    })?
}

/// The parts of a validated document (`blob`: the GLB binary chunk).
fn build(
    document: &Document,
    blob: Option<Vec<u8>>,
    path: &Path,
    format: &'static str,
    session: &mut Session<'_>,
) -> IngestResult<MeshAsset> {
    let buffers = &load_buffers(document, blob, path, format, session)?;
    let instances = mesh_instances(document);
    let declared: usize = instances
        .iter()
        .filter_map(|(node, _)| node.mesh())
        .flat_map(|m| m.primitives().collect::<Vec<_>>())
        .map(|p| declared_triangles(&p))
        .fold(0, usize::saturating_add);
    session.check_triangles(path, declared)?;

    let mut reader = Reader {
        document,
        path,
        format,
        buffers,
        asset: MeshAsset::default(),
        materials: HashMap::new(),
        textures: HashMap::new(),
    };
    for (node, world) in &instances {
        let Some(mesh) = node.mesh() else { continue };
        let mut pieces = Vec::new();
        for primitive in mesh.primitives() {
            if let Some(mut piece) = reader.primitive_mesh(&primitive)? {
                let material = reader.material(primitive.material(), session)?;
                piece.face_materials = Some(vec![material; piece.triangles.len()]);
                pieces.push(piece);
            }
        }
        if pieces.is_empty() {
            continue;
        }
        let name = node.name().or(mesh.name()).map_or_else(
            || format!("part_{}", reader.asset.parts.len()),
            str::to_owned,
        );
        reader.asset.parts.push(MeshPart {
            name,
            mesh: TriMesh::merge(&pieces).transformed(world),
        });
    }
    Ok(reader.asset)
}

/// Nodes with a mesh and their world transforms, depth-first from the default scene (else
/// scene 0, else every root node). Each node is visited once, so cycles cannot loop.
fn mesh_instances(document: &Document) -> Vec<(Node<'_>, DMat4)> {
    let roots: Vec<Node<'_>> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()).collect::<Vec<_>>())
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    let mut visited = HashSet::new();
    let mut out = Vec::new();
    let mut stack: Vec<(Node<'_>, DMat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        if !visited.insert(node.index()) {
            continue;
        }
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        if node.mesh().is_some() {
            out.push((node.clone(), world));
        }
        let children: Vec<Node<'_>> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
    }
    out
}

/// Triangles a primitive will produce, from its declared counts (nothing is read).
fn declared_triangles(primitive: &::gltf::Primitive<'_>) -> usize {
    let count = primitive
        .indices()
        .or_else(|| primitive.get(&Semantic::Positions))
        .map_or(0, |a| a.count());
    match primitive.mode() {
        Mode::Triangles => count / 3,
        Mode::TriangleStrip | Mode::TriangleFan => count.saturating_sub(2),
        _ => 0,
    }
}

/// Triangles of a primitive's index list, by mode (`None` for points and lines).
fn assemble(mode: Mode, idx: &[u32]) -> Option<Vec<[u32; 3]>> {
    let n = idx.len();
    Some(match mode {
        Mode::Triangles => idx.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [idx[i], idx[i + 1], idx[i + 2]]
                } else {
                    [idx[i + 1], idx[i], idx[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .map(|i| [idx[i], idx[i + 1], idx[0]])
            .collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => return None,
    })
}

struct Reader<'a> {
    document: &'a Document,
    path: &'a Path,
    format: &'static str,
    buffers: &'a [Vec<u8>],
    asset: MeshAsset,
    /// glTF material index (None = default material) -> asset material index.
    materials: HashMap<Option<usize>, u32>,
    /// glTF image index -> asset texture index.
    textures: HashMap<usize, usize>,
}

impl Reader<'_> {
    fn err(&self, message: String) -> IngestError {
        IngestError::parse(self.path, self.format, message)
    }

    /// A primitive's triangles with UVs and colours, in the mesh's frame.
    fn primitive_mesh(&self, primitive: &::gltf::Primitive<'_>) -> IngestResult<Option<TriMesh>> {
        let (path, format, buffers) = (self.path, self.format, self.buffers);
        if assemble(primitive.mode(), &[]).is_none() {
            return Ok(None); // points and lines
        }
        let Some(pos) = primitive.get(&Semantic::Positions) else {
            return Err(self.err(format!(
                "primitive {} has no POSITION attribute",
                primitive.index()
            )));
        };
        let Some((dims, values)) = read_floats(&pos, buffers, path, format)? else {
            return Ok(None);
        };
        if dims != 3 {
            return Err(self.err(format!(
                "POSITION accessor {} has {dims} components, expected 3",
                pos.index()
            )));
        }
        let positions: Vec<DVec3> = values
            .chunks_exact(3)
            .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
            .collect();
        let n = positions.len();
        let indices = match primitive.indices() {
            Some(acc) => read_indices(&acc, buffers, path, format)?.unwrap_or_default(),
            None => (0..u32::try_from(n).unwrap_or(u32::MAX)).collect(),
        };
        let Some(triangles) = assemble(primitive.mode(), &indices) else {
            return Ok(None);
        };
        let mut mesh = TriMesh {
            positions,
            triangles,
            ..TriMesh::default()
        };
        if let Some(acc) = primitive.get(&Semantic::TexCoords(0))
            && let Some((2, uv)) = read_floats(&acc, buffers, path, format)?
        {
            mesh.uvs = Some(uv.chunks_exact(2).map(|t| [t[0], t[1]]).collect());
        }
        if let Some(acc) = primitive.get(&Semantic::Colors(0)) {
            mesh.vertex_colors = match read_floats(&acc, buffers, path, format)? {
                Some((3, c)) => Some(c.chunks_exact(3).map(|c| [c[0], c[1], c[2], 1.0]).collect()),
                Some((4, c)) => Some(
                    c.chunks_exact(4)
                        .map(|c| [c[0], c[1], c[2], c[3]])
                        .collect(),
                ),
                _ => None,
            };
        }
        for (name, len) in [
            ("TEXCOORD_0", mesh.uvs.as_ref().map(Vec::len)),
            ("COLOR_0", mesh.vertex_colors.as_ref().map(Vec::len)),
        ] {
            if let Some(len) = len.filter(|&l| l != n) {
                return Err(self.err(format!("{name} has {len} entries but POSITION has {n}")));
            }
        }
        Ok(Some(mesh))
    }

    /// The asset material for a glTF material, created (with its texture) on first use.
    fn material(
        &mut self,
        material: ::gltf::Material<'_>,
        session: &mut Session<'_>,
    ) -> IngestResult<u32> {
        if let Some(&i) = self.materials.get(&material.index()) {
            return Ok(i);
        }
        let pbr = material.pbr_metallic_roughness();
        let texture = match pbr.base_color_texture() {
            Some(info) => match self.texture(&info.texture().source(), session) {
                Ok(index) => Some(index),
                // A missing image file costs only the look: the base colour stands in.
                Err(IngestError::MissingReference { reference, .. }) => {
                    session.warnings.push(format!(
                        "{} references the image {reference:?}, which does not exist; material {:?} uses its base colour",
                        self.path.display(),
                        material.name().unwrap_or_default()
                    ));
                    None
                }
                Err(e) => return Err(e),
            },
            None => None,
        };
        self.asset.materials.push(SurfaceMaterial {
            name: material.name().unwrap_or_default().to_owned(),
            base_color_rgba: pbr.base_color_factor(),
            base_color_texture: texture,
        });
        let index = u32::try_from(self.asset.materials.len() - 1).unwrap_or(u32::MAX);
        self.materials.insert(material.index(), index);
        Ok(index)
    }

    /// The asset texture for a glTF image, decoded on first use.
    fn texture(
        &mut self,
        image: &::gltf::Image<'_>,
        session: &mut Session<'_>,
    ) -> IngestResult<usize> {
        if let Some(&i) = self.textures.get(&image.index()) {
            return Ok(i);
        }
        // Read the source from the JSON: `Image::source` panics on a buffer view without a MIME
        // type, and the image format is sniffed from the bytes anyway.
        let json = self.document.as_json().images.get(image.index());
        let (view, uri) = json.map_or((None, None), |j| (j.buffer_view, j.uri.as_deref()));
        let (bytes, name) = match (view, uri) {
            (Some(view), _) => {
                let slice = self
                    .document
                    .views()
                    .nth(view.value())
                    .and_then(|v| {
                        let buffer = self.buffers.get(v.buffer().index())?;
                        buffer.get(v.offset()..v.offset().checked_add(v.length())?)
                    })
                    .ok_or_else(|| {
                        self.err(format!("image {} lies outside its buffer", image.index()))
                    })?;
                (slice.to_vec(), None)
            }
            (None, Some(uri)) => (
                load_uri(self.path, uri, self.format, session)?,
                (!uri.starts_with("data:")).then(|| uri.to_owned()),
            ),
            (None, None) => {
                return Err(self.err(format!(
                    "image {} has neither a uri nor a bufferView",
                    image.index()
                )));
            }
        };
        let name = image
            .name()
            .map(str::to_owned)
            .or(name)
            .unwrap_or_else(|| format!("image_{}", image.index()));
        self.asset
            .textures
            .push(decode_texture(self.path, &name, &bytes)?);
        let index = self.asset.textures.len() - 1;
        self.textures.insert(image.index(), index);
        Ok(index)
    }
}
