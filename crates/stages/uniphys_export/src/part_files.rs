//! The UniPhys-40K part files: `parts/part_<id>.obj` in the object frame with texture
//! coordinates and one `usemtl` per run of faces of a material, `parts/part_<id>.mtl` with each
//! material's colour and texture, and each texture once as `parts/texture_<t>.png`, so colours
//! sampled from the record (as the reference's point-cloud tool does) match the input's.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use uniphys_geometry::{SurfaceMaterial, Texture, TriMesh};
use uniphys_types::PartId;

use crate::obj_writer::{face_line, mtl_material, texcoord_line, vertex_line};
use crate::visuals::texture_file;
use crate::{Artifact, ExportError, ExportResult};

/// Name of the material written for faces without one.
const DEFAULT_MATERIAL: &str = "default";

fn material_name(index: Option<u32>, materials: &[SurfaceMaterial]) -> String {
    match index.and_then(|i| materials.get(i as usize).map(|m| (i, m))) {
        Some((i, m)) => {
            let clean: String = m
                .name
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            if clean.is_empty() {
                format!("m{i}")
            } else {
                format!("m{i}_{clean}")
            }
        }
        None => DEFAULT_MATERIAL.to_owned(),
    }
}

/// The material index and name a [`material_name`] stands for (`m3_oak` is material 3, `oak`);
/// `None` for the default material or a name that is not one.
pub(crate) fn material_of_name(written: &str) -> Option<(u32, String)> {
    let rest = written.strip_prefix('m')?;
    let (digits, name) = rest.split_once('_').unwrap_or((rest, ""));
    Some((digits.parse().ok()?, name.to_owned()))
}

/// OBJ and MTL of one part.
pub(crate) fn part_files(
    id: PartId,
    mesh: &TriMesh,
    materials: &[SurfaceMaterial],
    fallback_rgba: [f32; 4],
) -> Vec<Artifact> {
    let mut obj = String::with_capacity(mesh.positions.len() * 48 + mesh.triangles.len() * 32);
    let _ = writeln!(obj, "# written by uniphys\nmtllib {id}.mtl");
    for p in &mesh.positions {
        vertex_line(&mut obj, *p);
    }
    for uv in mesh.uvs.iter().flatten() {
        texcoord_line(&mut obj, *uv);
    }
    let face_material = |f: usize| mesh.face_materials.as_ref().map(|m| m[f]);
    let mut current: Option<Option<u32>> = None;
    let mut used: Vec<Option<u32>> = Vec::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        let m = face_material(f);
        if current != Some(m) {
            let _ = writeln!(obj, "usemtl {}", material_name(m, materials));
            current = Some(m);
            if !used.contains(&m) {
                used.push(m);
            }
        }
        face_line(&mut obj, *t, mesh.uvs.is_some());
    }
    let mut mtl = String::from("# written by uniphys\n");
    for m in used {
        let (rgba, texture) = match m.and_then(|i| materials.get(i as usize)) {
            Some(material) => (material.base_color_rgba, material.base_color_texture),
            None => (fallback_rgba, None),
        };
        let texture = texture.filter(|_| mesh.uvs.is_some());
        mtl_material(&mut mtl, &material_name(m, materials), rgba, texture);
    }
    vec![
        Artifact::new(format!("parts/{id}.obj"), obj.into_bytes()),
        Artifact::new(format!("parts/{id}.mtl"), mtl.into_bytes()),
    ]
}

/// Every texture that a part with texture coordinates uses, once, as PNG in `parts/`, with its
/// index.
pub(crate) fn texture_files(
    meshes: &[TriMesh],
    materials: &[SurfaceMaterial],
    textures: &[Texture],
) -> ExportResult<Vec<(usize, Artifact)>> {
    let used: BTreeSet<usize> = meshes
        .iter()
        .filter(|m| m.uvs.is_some())
        .flat_map(|m| m.face_materials.iter().flatten())
        .filter_map(|&i| materials.get(i as usize).and_then(|m| m.base_color_texture))
        .collect();
    let mut out = Vec::with_capacity(used.len());
    for t in used {
        let texture = textures.get(t).ok_or_else(|| {
            ExportError::InputMismatch(format!(
                "material refers to texture {t}, which does not exist"
            ))
        })?;
        out.push((
            t,
            Artifact::new(format!("parts/{}", texture_file(t)), encode_png(texture)?),
        ));
    }
    Ok(out)
}

fn encode_png(texture: &Texture) -> ExportResult<Vec<u8>> {
    let image = image::RgbaImage::from_raw(texture.width, texture.height, texture.rgba8.clone())
        .ok_or_else(|| {
            ExportError::InputMismatch(format!(
                "texture {:?} has {} bytes for {}x{} pixels",
                texture.name,
                texture.rgba8.len(),
                texture.width,
                texture.height
            ))
        })?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| {
            ExportError::InputMismatch(format!(
                "texture {:?} could not be encoded as PNG: {e}",
                texture.name
            ))
        })?;
    Ok(bytes.into_inner())
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;

    fn textured_quad() -> (TriMesh, Vec<SurfaceMaterial>, Vec<Texture>) {
        let mesh = TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .and_then(|m| m.with_uvs(vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]))
        .and_then(|m| m.with_face_materials(vec![0, 1]))
        .unwrap();
        let materials = vec![
            SurfaceMaterial {
                name: "wood oak".into(),
                base_color_rgba: [1.0, 1.0, 1.0, 1.0],
                base_color_texture: Some(0),
            },
            SurfaceMaterial {
                name: "".into(),
                base_color_rgba: [0.5, 0.25, 0.0, 1.0],
                base_color_texture: None,
            },
        ];
        let textures = vec![Texture {
            name: "grain".into(),
            width: 2,
            height: 1,
            rgba8: vec![255, 0, 0, 255, 0, 255, 0, 255],
        }];
        (mesh, materials, textures)
    }

    #[test]
    fn obj_keeps_uvs_flipped_and_switches_material_per_run_of_faces() {
        let (mesh, materials, _) = textured_quad();
        let files = part_files(PartId(3), &mesh, &materials, [0.6; 4]);
        let obj = String::from_utf8(files[0].bytes.clone()).unwrap();
        assert!(obj.contains("mtllib part_3.mtl\n"));
        assert!(obj.contains("vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"), "{obj}");
        assert!(
            obj.contains("usemtl m0_wood_oak\nf 1/1 2/2 3/3\nusemtl m1\nf 1/1 3/3 4/4\n"),
            "{obj}"
        );
        let mtl = String::from_utf8(files[1].bytes.clone()).unwrap();
        assert!(
            mtl.contains("newmtl m0_wood_oak\nKd 1 1 1\nd 1\nmap_Kd texture_0.png\n"),
            "{mtl}"
        );
        assert!(mtl.contains("newmtl m1\nKd 0.5 0.25 0\nd 1\n"), "{mtl}");
    }

    #[test]
    fn each_used_texture_is_written_once_as_a_png_that_decodes_to_its_pixels() {
        let (mesh, materials, textures) = textured_quad();
        let files = texture_files(&[mesh.clone(), mesh], &materials, &textures).unwrap();
        assert_eq!(files.len(), 1);
        assert_eq!(files[0].0, 0);
        assert_eq!(files[0].1.path, "parts/texture_0.png");
        let decoded = image::load_from_memory(&files[0].1.bytes)
            .unwrap()
            .to_rgba8();
        assert_eq!(decoded.into_raw(), textures[0].rgba8);
    }

    #[test]
    fn a_written_material_name_reads_back_as_its_index_and_name() {
        let (_, materials, _) = textured_quad();
        let written: Vec<String> = (0..2).map(|i| material_name(Some(i), &materials)).collect();
        assert_eq!(written, ["m0_wood_oak", "m1"]);
        assert_eq!(
            material_of_name(&written[0]),
            Some((0, "wood_oak".to_owned()))
        );
        assert_eq!(material_of_name(&written[1]), Some((1, String::new())));
        assert_eq!(material_of_name("default"), None);
    }

    #[test]
    fn parts_without_materials_get_the_fallback_colour() {
        let mesh = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let files = part_files(PartId(0), &mesh, &[], [0.6, 0.6, 0.6, 1.0]);
        let mtl = String::from_utf8(files[1].bytes.clone()).unwrap();
        assert_eq!(
            mtl,
            "# written by uniphys\nnewmtl default\nKd 0.6 0.6 0.6\nd 1\n"
        );
        assert!(
            String::from_utf8(files[0].bytes.clone())
                .unwrap()
                .contains("usemtl default\nf 1 3 2\n")
        );
    }
}
