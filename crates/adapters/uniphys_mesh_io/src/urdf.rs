//! URDF (PartNet-Mobility style): every link with geometry becomes one part (its visuals, or its
//! collisions if it has no visual, merged and placed at the zero configuration); joints are
//! converted by [`crate::urdf_joints`]. Mesh files may be OBJ, STL or PLY; primitives are
//! tessellated by [`crate::primitives`].

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use uniphys_geometry::{DMat4, DVec3, MeshAsset, MeshPart, SurfaceMaterial, TriMesh};
use urdf_rs::Geometry;

use crate::checks::sanitize;
use crate::guard::guarded;
use crate::paths::resolve_urdf_reference;
use crate::primitives::{box_mesh, capsule_mesh, cylinder_mesh, sphere_mesh};
use crate::source::Session;
use crate::urdf_joints::part_joints;
use crate::urdf_tree::{Tree, pose_matrix};
use crate::{IngestError, IngestResult, obj, ply, stl};

/// Deepest element nesting accepted (real URDFs nest about 5 deep).
const MAX_DEPTH: usize = 64;

/// Reads a URDF file (at canonical `path`) and the meshes it references.
pub(crate) fn read_urdf(
    path: &Path,
    bytes: &[u8],
    session: &mut Session<'_>,
) -> IngestResult<MeshAsset> {
    let parse_err = |m: String| IngestError::parse(path, "urdf", m);
    let text = std::str::from_utf8(bytes).map_err(|e| parse_err(format!("not UTF-8 text: {e}")))?;
    let depth = max_nesting(text);
    if depth > MAX_DEPTH {
        return Err(parse_err(format!(
            "elements are nested {depth} deep, more than {MAX_DEPTH}"
        )));
    }
    let patched = guarded(path, "urdf", || repair_for_urdf_rs(text))?.map_err(parse_err)?;
    let robot = guarded(path, "urdf", || urdf_rs::read_from_string(&patched))?
        .map_err(|e| parse_err(e.to_string()))?;
    let tree = Tree::new(&robot, path)?;
    let mut builder = Builder {
        path,
        urdf_dir: path.parent().unwrap_or(Path::new("/")).to_path_buf(),
        robot: &robot,
        asset: MeshAsset::default(),
        meshes: HashMap::new(),
        materials: HashMap::new(),
    };
    let mut part_of_link = vec![None; robot.links.len()];
    for (li, link) in robot.links.iter().enumerate() {
        let geometries: Vec<(&urdf_rs::Pose, &Geometry, Option<&urdf_rs::Material>)> =
            if link.visual.is_empty() {
                link.collision
                    .iter()
                    .map(|c| (&c.origin, &c.geometry, None))
                    .collect()
            } else {
                link.visual
                    .iter()
                    .map(|v| (&v.origin, &v.geometry, v.material.as_ref()))
                    .collect()
            };
        // A primitive of zero size (PyBullet's laikago toes are spheres of radius 0) has no
        // surface: leave it out and say so, as if the link had no such geometry.
        let (zero, geometries): (Vec<_>, Vec<_>) = geometries
            .into_iter()
            .partition(|(_, g, _)| is_zero_size(g));
        if !zero.is_empty() {
            session.warnings.push(format!(
                "{}: link {:?} has {} zero-size primitive(s); left out",
                path.display(),
                link.name,
                zero.len()
            ));
        }
        if geometries.is_empty() {
            continue;
        }
        let mut pieces = Vec::with_capacity(geometries.len());
        for (origin, geometry, material) in geometries {
            let local = pose_matrix(origin).ok_or_else(|| {
                IngestError::urdf(
                    path,
                    format!(
                        "link {:?} has a geometry with a non-finite <origin>",
                        link.name
                    ),
                )
            })?;
            let piece = builder.geometry(&link.name, geometry, material, session)?;
            session.add_triangles(path, piece.triangles.len())?;
            pieces.push(piece.transformed(&(tree.link_world[li] * local)));
        }
        part_of_link[li] = Some(builder.asset.parts.len());
        builder.asset.parts.push(MeshPart {
            name: link.name.clone(),
            mesh: TriMesh::merge(&pieces),
        });
    }
    let mut asset = builder.asset;
    asset.joints = part_joints(&robot, &tree, &part_of_link, path)?;
    Ok(asset)
}

/// Whether a primitive has a zero dimension (and no negative or non-finite one, which stays an
/// error).
fn is_zero_size(geometry: &Geometry) -> bool {
    let dims: Vec<f64> = match geometry {
        Geometry::Box { size } => size.0.to_vec(),
        Geometry::Cylinder { radius, length } | Geometry::Capsule { radius, length } => {
            vec![*radius, *length]
        }
        Geometry::Sphere { radius } => vec![*radius],
        Geometry::Mesh { .. } => return false,
    };
    dims.iter().all(|d| d.is_finite() && *d >= 0.0) && dims.contains(&0.0)
}

struct Builder<'a> {
    path: &'a Path,
    urdf_dir: PathBuf,
    robot: &'a urdf_rs::Robot,
    asset: MeshAsset,
    /// Mesh files already loaded (canonical path -> merged mesh, asset material indices).
    meshes: HashMap<PathBuf, TriMesh>,
    /// URDF materials already added (name and colour bits -> asset material index).
    materials: HashMap<(String, [u64; 4]), u32>,
}

impl Builder<'_> {
    /// One visual or collision geometry in its own frame, with face materials.
    fn geometry(
        &mut self,
        link: &str,
        geometry: &Geometry,
        material: Option<&urdf_rs::Material>,
        session: &mut Session<'_>,
    ) -> IngestResult<TriMesh> {
        let positive = |what: &str, values: &[f64]| {
            if values.iter().all(|v| v.is_finite() && *v > 0.0) {
                Ok(())
            } else {
                Err(IngestError::urdf(
                    self.path,
                    format!(
                        "link {link:?} has a {what} of {values:?}; dimensions must be finite and positive"
                    ),
                ))
            }
        };
        let mut mesh = match geometry {
            Geometry::Box { size } => {
                positive("box size", &size.0)?;
                box_mesh(DVec3::from_array(size.0))
            }
            Geometry::Cylinder { radius, length } => {
                positive("cylinder radius and length", &[*radius, *length])?;
                cylinder_mesh(*radius, *length)
            }
            Geometry::Capsule { radius, length } => {
                positive("capsule radius and length", &[*radius, *length])?;
                capsule_mesh(*radius, *length)
            }
            Geometry::Sphere { radius } => {
                positive("sphere radius", &[*radius])?;
                sphere_mesh(*radius)
            }
            Geometry::Mesh { filename, scale } => {
                let scale = scale.map_or(DVec3::ONE, |s| DVec3::from_array(s.0));
                if !scale.is_finite() {
                    return Err(IngestError::urdf(
                        self.path,
                        format!("link {link:?} has a non-finite mesh scale"),
                    ));
                }
                let file =
                    resolve_urdf_reference(self.path, &self.urdf_dir, &session.root, filename)?;
                self.mesh_file(&file, session)?
                    .transformed(&DMat4::from_scale(scale))
            }
        };
        if mesh.face_materials.is_none() {
            let m = self.visual_material(material);
            mesh.face_materials = Some(vec![m; mesh.triangles.len()]);
        }
        Ok(mesh)
    }

    /// A mesh file's parts merged, loaded and checked once; its materials join the asset.
    fn mesh_file(&mut self, file: &Path, session: &mut Session<'_>) -> IngestResult<TriMesh> {
        if let Some(mesh) = self.meshes.get(file) {
            return Ok(mesh.clone());
        }
        let ext = file
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        if !matches!(ext.as_str(), "obj" | "stl" | "ply") {
            let what = if ext == "dae" {
                "a COLLADA (.dae) mesh; convert it to OBJ or STL".to_owned()
            } else {
                format!("a .{ext} mesh in a URDF; use OBJ, STL or PLY")
            };
            return Err(IngestError::Unsupported {
                path: file.to_path_buf(),
                what,
            });
        }
        let bytes = session.read(file)?;
        let mut sub = match ext.as_str() {
            "obj" => obj::read_obj(file, &bytes, session)?,
            "ply" => ply::read_ply(file, &bytes, session)?,
            _ => stl::read_stl(file, bytes, session)?,
        };
        sanitize(&mut sub, file, session)?;
        let texture_offset = self.asset.textures.len();
        let material_offset = u32::try_from(self.asset.materials.len()).unwrap_or(u32::MAX);
        self.asset.textures.append(&mut sub.textures);
        for mut material in sub.materials {
            material.base_color_texture = material.base_color_texture.map(|t| t + texture_offset);
            self.asset.materials.push(material);
        }
        let mut merged = TriMesh::merge(sub.parts.iter().map(|p| &p.mesh));
        if let Some(face_materials) = &mut merged.face_materials {
            face_materials
                .iter_mut()
                .for_each(|m| *m += material_offset);
        }
        self.meshes.insert(file.to_path_buf(), merged.clone());
        Ok(merged)
    }

    /// The asset material for a URDF `<material>` (its colour, or the robot-level material of
    /// the same name); white if none. URDF textures are not read.
    fn visual_material(&mut self, material: Option<&urdf_rs::Material>) -> u32 {
        let name = material.map(|m| m.name.clone()).unwrap_or_default();
        let rgba = material
            .and_then(|m| m.color.as_ref())
            .or_else(|| {
                self.robot
                    .materials
                    .iter()
                    .find(|m| !name.is_empty() && m.name == name)
                    .and_then(|m| m.color.as_ref())
            })
            .map_or([1.0; 4], |c| c.rgba.0);
        let key = (name.clone(), rgba.map(f64::to_bits));
        if let Some(&i) = self.materials.get(&key) {
            return i;
        }
        #[expect(clippy::cast_possible_truncation, reason = "colour channel precision")]
        let base_color_rgba = rgba.map(|v| v.clamp(0.0, 1.0) as f32);
        self.asset.materials.push(SurfaceMaterial {
            name,
            base_color_rgba,
            base_color_texture: None,
        });
        let index = u32::try_from(self.asset.materials.len() - 1).unwrap_or(u32::MAX);
        self.materials.insert(key, index);
        index
    }
}

/// Upper bound of the element nesting depth (comments, declarations and processing
/// instructions skipped), so recursive XML code cannot overflow the stack.
fn max_nesting(text: &str) -> usize {
    let b = text.as_bytes();
    let (mut depth, mut max, mut i) = (0usize, 0usize, 0usize);
    while i < b.len() {
        if b[i..].starts_with(b"<!--") {
            i = text[i..].find("-->").map_or(b.len(), |e| i + e + 3);
            continue;
        }
        match (b[i], b.get(i + 1)) {
            (b'<', Some(b'/')) | (b'/', Some(b'>')) => depth = depth.saturating_sub(1),
            (b'<', Some(b'?' | b'!')) | (b'<', None) => {}
            (b'<', Some(_)) => {
                depth += 1;
                max = max.max(depth);
            }
            _ => {}
        }
        i += 1;
    }
    max
}

/// Repairs two habits of real URDFs that urdf-rs refuses: PartNet-Mobility writes
/// `<limit lower upper/>` without the `velocity` that urdf-rs requires for URDF < 1.2 (add
/// `velocity="0"`), and some files separate vector components with commas
/// (`xyz="0.07, 0, -0.69"`; read them as spaces).
fn repair_for_urdf_rs(text: &str) -> Result<String, String> {
    fn visit(element: &mut xml::Element) {
        for key in ["xyz", "rpy", "size", "scale"] {
            if let Some(value) = element.get_attribute(key, None).filter(|v| v.contains(',')) {
                let spaced = value.replace(',', " ");
                element.set_attribute(key.to_owned(), None, spaced);
            }
        }
        let is_joint = element.name == "joint";
        for child in &mut element.children {
            if let xml::Xml::ElementNode(child) = child {
                if is_joint
                    && child.name == "limit"
                    && child.get_attribute("velocity", None).is_none()
                {
                    child.set_attribute("velocity".to_owned(), None, "0".to_owned());
                }
                visit(child);
            }
        }
    }
    let mut root: xml::Element = text.parse().map_err(|e: xml::BuilderError| e.to_string())?;
    visit(&mut root);
    Ok(root.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_depth_counts_open_elements_only() {
        assert_eq!(
            max_nesting("<?xml version=\"1.0\"?><a><b/><c><d></d></c></a>"),
            3
        );
        assert_eq!(max_nesting("<!-- <x><y><z> --><a/>"), 1);
        let deep = "<a>".repeat(100);
        assert_eq!(max_nesting(&deep), 100);
    }

    #[test]
    fn comma_separated_vectors_read_as_spaces() {
        let text = r#"<robot name="r"><link name="a"><visual><origin xyz="0.07, 0, -0.69" rpy="0 0 0"/>
            <geometry><box size="1,2,3"/></geometry></visual></link></robot>"#;
        assert!(urdf_rs::read_from_string(text).is_err());
        let robot = urdf_rs::read_from_string(&repair_for_urdf_rs(text).expect("parses"))
            .expect("accepted");
        assert_eq!(robot.links[0].visual[0].origin.xyz.0, [0.07, 0.0, -0.69]);
    }

    #[test]
    fn limit_without_velocity_gets_one_so_urdf_rs_accepts_it() {
        let text = r#"<robot name="r"><link name="a"/><link name="b"/>
            <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
            <limit lower="0" upper="1.5"/></joint></robot>"#;
        assert!(urdf_rs::read_from_string(text).is_err());
        let patched = repair_for_urdf_rs(text).expect("parses");
        let robot = urdf_rs::read_from_string(&patched).expect("accepted");
        assert!((robot.joints[0].limit.upper - 1.5).abs() < 1e-12);
    }
}
