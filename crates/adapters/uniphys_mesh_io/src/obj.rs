//! Wavefront OBJ with MTL materials: every object/group is a part, MTL `Kd` (and `d`) give the
//! base colour, `map_Kd` the base colour texture. A missing MTL or texture image is a warning
//! (the geometry loads; the base colour stands in).

use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use uniphys_geometry::{DVec3, MeshAsset, MeshPart, SurfaceMaterial, TriMesh};

use crate::guard::guarded;
use crate::paths::resolve_reference;
use crate::source::Session;
use crate::texture::decode_texture;
use crate::{IngestError, IngestResult};

/// What tobj's material loader returns: the materials and their index by name.
type MtlData = (Vec<tobj::Material>, HashMap<String, usize>);

/// An MTL library as loaded: where it is and how many materials it added.
struct MtlLib {
    path: PathBuf,
    count: usize,
}

/// Reads an OBJ file (at canonical `path`) and the MTL files and textures it references.
pub(crate) fn read_obj(
    path: &Path,
    bytes: &[u8],
    session: &mut Session<'_>,
) -> IngestResult<MeshAsset> {
    let base_dir = path.parent().unwrap_or(Path::new("/")).to_path_buf();
    let warnings_before = session.warnings.len();
    let state = RefCell::new((&mut *session, None::<IngestError>, Vec::<MtlLib>::new()));
    let loader = |reference: &Path| -> tobj::MTLLoadResult {
        let mut guard = state.borrow_mut();
        let (session, error, libs) = &mut *guard;
        if error.is_some() {
            return Err(tobj::LoadError::OpenFileFailed);
        }
        let result = load_mtl(path, &base_dir, reference, session);
        match result {
            Ok((mtl_path, loaded)) => {
                libs.push(MtlLib {
                    path: mtl_path,
                    count: loaded.0.len(),
                });
                Ok(loaded)
            }
            // A missing MTL costs only colours and material names: load the geometry, say so.
            Err(IngestError::MissingReference { reference, .. }) => {
                session.warnings.push(format!(
                    "{} references the material library {reference:?}, which does not exist; loaded without its materials",
                    path.display()
                ));
                Err(tobj::LoadError::OpenFileFailed)
            }
            Err(e) => {
                *error = Some(e);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    #[allow(
        clippy::needless_update,
        reason = "tobj adds fields under its optional features; keep their defaults"
    )]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
        ..tobj::LoadOptions::default()
    };
    // Names in files from older tools are often Latin-1; read them lossily rather than fail.
    let text = String::from_utf8_lossy(bytes);
    let loaded = guarded(path, "obj", || {
        tobj::load_obj_buf(&mut Cursor::new(text.as_bytes()), &options, loader)
    })?;
    let (_, error, libs) = state.into_inner();
    if let Some(e) = error {
        return Err(e);
    }
    let (models, materials) = loaded.map_err(|e| IngestError::parse(path, "obj", e.to_string()))?;
    let materials = match materials {
        Ok(materials) => materials,
        Err(_) if session.warnings.len() > warnings_before => Vec::new(),
        Err(e) => return Err(IngestError::parse(path, "mtl", e.to_string())),
    };

    let mut asset = MeshAsset::default();
    load_materials(&materials, &libs, &mut asset, session)?;
    let default_material = u32::try_from(asset.materials.len()).unwrap_or(u32::MAX);
    let mut uses_default = false;
    let mut by_name: Vec<(String, Vec<TriMesh>)> = Vec::new();
    let mut triangles = 0usize;
    for model in &models {
        let material = match model.mesh.material_id {
            Some(i) if i < asset.materials.len() => u32::try_from(i).unwrap_or(u32::MAX),
            _ => {
                uses_default = true;
                default_material
            }
        };
        let mesh = model_mesh(
            &model.mesh,
            (!asset.materials.is_empty()).then_some(material),
        );
        triangles = triangles.saturating_add(mesh.triangles.len());
        session.check_triangles(path, triangles)?;
        match by_name.iter_mut().find(|(n, _)| *n == model.name) {
            Some((_, meshes)) => meshes.push(mesh),
            None => by_name.push((model.name.clone(), vec![mesh])),
        }
    }
    if uses_default && !asset.materials.is_empty() {
        asset.materials.push(default_surface());
    }
    for (i, (name, meshes)) in by_name.into_iter().enumerate() {
        let name = if name.is_empty() {
            format!("part_{i}")
        } else {
            name
        };
        asset.parts.push(MeshPart {
            name,
            mesh: TriMesh::merge(&meshes),
        });
    }
    Ok(asset)
}

/// The white material used for faces without one.
pub(crate) fn default_surface() -> SurfaceMaterial {
    SurfaceMaterial {
        name: String::new(),
        base_color_rgba: [1.0; 4],
        base_color_texture: None,
    }
}

fn load_mtl(
    obj: &Path,
    base_dir: &Path,
    reference: &Path,
    session: &mut Session<'_>,
) -> IngestResult<(PathBuf, MtlData)> {
    let reference = reference.to_string_lossy();
    let mtl_path = resolve_reference(obj, base_dir, &session.root, &reference)?;
    let bytes = session.read(&mtl_path)?;
    let parsed = guarded(&mtl_path, "mtl", || {
        tobj::load_mtl_buf(&mut Cursor::new(String::from_utf8_lossy(&bytes).as_bytes()))
    })?
    .map_err(|e| IngestError::parse(&mtl_path, "mtl", e.to_string()))?;
    Ok((mtl_path, parsed))
}

/// Turns the MTL materials into surface materials, loading each `map_Kd` texture once.
fn load_materials(
    materials: &[tobj::Material],
    libs: &[MtlLib],
    asset: &mut MeshAsset,
    session: &mut Session<'_>,
) -> IngestResult<()> {
    let mut lib_of = libs
        .iter()
        .flat_map(|lib| std::iter::repeat_n(lib, lib.count));
    let mut textures: HashMap<PathBuf, usize> = HashMap::new();
    for material in materials {
        let lib = lib_of.next();
        let [r, g, b] = material.diffuse.unwrap_or([1.0; 3]);
        let alpha = material.dissolve.unwrap_or(1.0).clamp(0.0, 1.0);
        let texture = match (&material.diffuse_texture, lib) {
            (Some(reference), Some(lib)) => {
                let file = texture_file_name(reference);
                let dir = lib.path.parent().unwrap_or(Path::new("/"));
                let tex_path = match resolve_reference(&lib.path, dir, &session.root, file) {
                    Ok(p) => p,
                    // A missing image costs only the look: the base colour stands in.
                    Err(IngestError::MissingReference { reference, .. }) => {
                        session.warnings.push(format!(
                            "{} references the texture {reference:?}, which does not exist; material {:?} uses its base colour",
                            lib.path.display(),
                            material.name
                        ));
                        asset.materials.push(SurfaceMaterial {
                            name: material.name.clone(),
                            base_color_rgba: [r, g, b, alpha],
                            base_color_texture: None,
                        });
                        continue;
                    }
                    Err(e) => return Err(e),
                };
                let index = match textures.get(&tex_path) {
                    Some(&i) => i,
                    None => {
                        let bytes = session.read(&tex_path)?;
                        asset
                            .textures
                            .push(decode_texture(&lib.path, file, &bytes)?);
                        textures.insert(tex_path, asset.textures.len() - 1);
                        asset.textures.len() - 1
                    }
                };
                Some(index)
            }
            _ => None,
        };
        asset.materials.push(SurfaceMaterial {
            name: material.name.clone(),
            base_color_rgba: [r, g, b, alpha],
            base_color_texture: texture,
        });
    }
    Ok(())
}

/// The file name of a `map_Kd` statement, skipping options such as `-s 1 1 1`.
fn texture_file_name(statement: &str) -> &str {
    let statement = statement.trim();
    if statement.starts_with('-') {
        statement.split_whitespace().last().unwrap_or(statement)
    } else {
        statement
    }
}

/// One tobj model as a mesh; UVs flipped to the glTF convention (v down).
fn model_mesh(mesh: &tobj::Mesh, material: Option<u32>) -> TriMesh {
    let n = mesh.positions.len() / 3;
    let positions: Vec<DVec3> = mesh
        .positions
        .chunks_exact(3)
        .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
        .collect();
    let triangles: Vec<[u32; 3]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let uvs = (n > 0 && mesh.texcoords.len() == 2 * n).then(|| {
        mesh.texcoords
            .chunks_exact(2)
            .map(|t| [t[0], 1.0 - t[1]])
            .collect()
    });
    let vertex_colors = (n > 0 && mesh.vertex_color.len() == 3 * n).then(|| {
        mesh.vertex_color
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2], 1.0])
            .collect()
    });
    TriMesh {
        face_materials: material.map(|m| vec![m; triangles.len()]),
        positions,
        triangles,
        uvs,
        vertex_colors,
    }
}
