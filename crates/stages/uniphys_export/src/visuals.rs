//! The visual meshes of a link: a part drawn with base-colour textures is split by material, so
//! each simulator model can give every piece its material and texture (an MJCF geom takes one
//! material); a part without textures stays one mesh in the link's colour.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use uniphys_geometry::{DVec3, SurfaceMaterial, TriMesh};

use crate::obj_writer::{face_line, mtl_material, texcoord_line, vertex_line};

/// A piece smaller than this (vertices) is drawn with the largest piece: MuJoCo refuses meshes
/// with fewer than four vertices.
const PIECE_VERTICES_MIN: usize = 4;

/// One visual mesh of a link: the faces of its part drawn with one look.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Visual {
    /// File stem: `part_<id>_visual` for the faces in the link's colour, `part_<id>_visual_m<k>`
    /// for the faces of textured material `k`.
    pub stem: String,
    /// Material name, unique in the model.
    pub material: String,
    /// Linear RGBA: the link's colour, or the textured material's base colour (which multiplies
    /// its texture).
    pub rgba: [f32; 4],
    /// Index of the base-colour texture (into the export input's textures), if any.
    pub texture: Option<usize>,
    /// Faces of the part mesh the piece holds, ascending.
    pub faces: Vec<usize>,
}

/// File name of texture `index` beside the link meshes and in `parts/`.
pub(crate) fn texture_file(index: usize) -> String {
    format!("texture_{index}.png")
}

/// The texture index a [`texture_file`] name stands for.
pub(crate) fn texture_of_file(file: &str) -> Option<usize> {
    file.strip_prefix("texture_")?
        .strip_suffix(".png")?
        .parse()
        .ok()
}

/// The visuals of the part `stem_prefix` (`part_<id>`, link `link_name`): one per textured
/// material its faces use (when the mesh has texture coordinates), and one in `rgba` for the
/// other faces.
pub(crate) fn link_visuals(
    stem_prefix: &str,
    link_name: &str,
    mesh: &TriMesh,
    materials: &[SurfaceMaterial],
    rgba: [f32; 4],
) -> Vec<Visual> {
    let all_faces = || (0..mesh.triangles.len()).collect::<Vec<_>>();
    let plain = |faces: Vec<usize>| Visual {
        stem: format!("{stem_prefix}_visual"),
        material: format!("{link_name}_material"),
        rgba,
        texture: None,
        faces,
    };
    let (Some(_), Some(face_materials)) = (&mesh.uvs, &mesh.face_materials) else {
        return vec![plain(all_faces())];
    };
    let textured = |f: usize| {
        let m = face_materials[f];
        materials
            .get(m as usize)
            .and_then(|mat| mat.base_color_texture.map(|t| (m, mat.base_color_rgba, t)))
    };
    let mut by_material: BTreeMap<u32, ([f32; 4], usize, Vec<usize>)> = BTreeMap::new();
    let mut rest = Vec::new();
    for f in 0..mesh.triangles.len() {
        match textured(f) {
            Some((m, colour, t)) => by_material
                .entry(m)
                .or_insert((colour, t, Vec::new()))
                .2
                .push(f),
            None => rest.push(f),
        }
    }
    if by_material.is_empty() {
        return vec![plain(rest)];
    }
    let mut visuals: Vec<Visual> = by_material
        .into_iter()
        .map(|(m, (colour, t, faces))| Visual {
            stem: format!("{stem_prefix}_visual_m{m}"),
            material: format!("{link_name}_m{m}_material"),
            rgba: colour,
            texture: Some(t),
            faces,
        })
        .collect();
    if !rest.is_empty() {
        visuals.push(plain(rest));
    }
    fold_small_pieces(mesh, visuals)
}

/// The vertices `faces` use, in the order they first do, and each mesh vertex's new index among
/// them (`u32::MAX` for those not used).
fn used_vertices(mesh: &TriMesh, faces: &[usize]) -> (Vec<u32>, Vec<usize>) {
    let mut index = vec![u32::MAX; mesh.positions.len()];
    let mut order = Vec::new();
    for &f in faces {
        for v in mesh.triangles[f] {
            if index[v as usize] == u32::MAX {
                index[v as usize] = u32::try_from(order.len()).unwrap_or(u32::MAX);
                order.push(v as usize);
            }
        }
    }
    (index, order)
}

/// Pieces under [`PIECE_VERTICES_MIN`] vertices join the piece with the most faces.
fn fold_small_pieces(mesh: &TriMesh, mut visuals: Vec<Visual>) -> Vec<Visual> {
    if visuals.len() < 2 {
        return visuals;
    }
    let (small, mut kept): (Vec<Visual>, Vec<Visual>) = visuals
        .drain(..)
        .partition(|v| used_vertices(mesh, &v.faces).1.len() < PIECE_VERTICES_MIN);
    if kept.is_empty() {
        // Every piece is tiny: one piece, drawn as the first was.
        let mut all = small;
        let mut first = all.remove(0);
        first.faces.extend(all.into_iter().flat_map(|v| v.faces));
        first.faces.sort_unstable();
        return vec![first];
    }
    let largest = (0..kept.len())
        .max_by_key(|&i| (kept[i].faces.len(), std::cmp::Reverse(i)))
        .unwrap_or(0);
    for piece in small {
        kept[largest].faces.extend(piece.faces);
    }
    kept[largest].faces.sort_unstable();
    kept
}

/// The OBJ of `visual` (its faces of `mesh`, translated by `-origin` into the link frame) and,
/// for a textured piece, its MTL: texture coordinates in OBJ's convention (v up the image) and
/// `map_Kd`, which URDF importers (PyBullet, yourdfpy) read; MuJoCo reads the coordinates and
/// takes the texture from the MJCF.
pub(crate) fn visual_files(
    mesh: &TriMesh,
    visual: &Visual,
    origin: DVec3,
) -> (Vec<u8>, Option<Vec<u8>>) {
    // A piece holding every face keeps the mesh's vertices as they are; another keeps those its
    // faces use, in the order they first do.
    let (index, order) = if visual.faces.len() == mesh.triangles.len() {
        let all = 0..mesh.positions.len();
        (
            all.clone()
                .map(|v| u32::try_from(v).unwrap_or(u32::MAX))
                .collect(),
            all.collect(),
        )
    } else {
        used_vertices(mesh, &visual.faces)
    };
    let uvs = mesh.uvs.as_ref().filter(|_| visual.texture.is_some());
    let mut obj = String::with_capacity(order.len() * 48 + visual.faces.len() * 32);
    obj.push_str("# written by uniphys\n");
    if uvs.is_some() {
        let _ = writeln!(
            obj,
            "mtllib {}.mtl\nusemtl {}",
            visual.stem, visual.material
        );
    }
    for &v in &order {
        vertex_line(&mut obj, mesh.positions[v] - origin);
    }
    if let Some(uvs) = uvs {
        for &v in &order {
            texcoord_line(&mut obj, uvs[v]);
        }
    }
    for &f in &visual.faces {
        face_line(
            &mut obj,
            mesh.triangles[f].map(|v| index[v as usize]),
            uvs.is_some(),
        );
    }
    let mtl = visual.texture.filter(|_| uvs.is_some()).map(|t| {
        let mut mtl = String::from("# written by uniphys\n");
        mtl_material(&mut mtl, &visual.material, visual.rgba, Some(t));
        mtl.into_bytes()
    });
    (obj.into_bytes(), mtl)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads side by side, the left one in textured material 1, the right one in plain
    /// material 0, with texture coordinates.
    fn two_quads() -> (TriMesh, Vec<SurfaceMaterial>) {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
        ];
        let mut mesh = TriMesh::new(positions, vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]])
            .expect("mesh");
        mesh.uvs = Some(vec![
            [0.0, 1.0],
            [0.5, 1.0],
            [0.5, 0.0],
            [0.0, 0.0],
            [1.0, 1.0],
            [1.0, 0.0],
        ]);
        mesh.face_materials = Some(vec![1, 1, 0, 0]);
        let materials = vec![
            SurfaceMaterial {
                name: "paint".into(),
                base_color_rgba: [0.2, 0.3, 0.4, 1.0],
                base_color_texture: None,
            },
            SurfaceMaterial {
                name: "label".into(),
                base_color_rgba: [1.0, 1.0, 1.0, 1.0],
                base_color_texture: Some(3),
            },
        ];
        (mesh, materials)
    }

    #[test]
    fn a_textured_material_is_a_piece_of_its_own_with_its_texture() {
        let (mesh, materials) = two_quads();
        let visuals = link_visuals("part_2", "part_2_box", &mesh, &materials, [0.5; 4]);
        assert_eq!(visuals.len(), 2, "{visuals:?}");
        assert_eq!(visuals[0].stem, "part_2_visual_m1");
        assert_eq!(visuals[0].texture, Some(3));
        assert_eq!(visuals[0].faces, vec![0, 1]);
        assert_eq!(visuals[1].stem, "part_2_visual");
        assert_eq!(visuals[1].texture, None);
        assert_eq!(visuals[1].rgba, [0.5; 4]);
        assert_eq!(visuals[1].faces, vec![2, 3]);
    }

    #[test]
    fn a_texture_file_reads_back_as_its_index() {
        assert_eq!(texture_of_file(&texture_file(7)), Some(7));
        assert_eq!(texture_of_file("label.png"), None);
    }

    #[test]
    fn a_part_without_texture_coordinates_is_one_plain_piece() {
        let (mut mesh, materials) = two_quads();
        mesh.uvs = None;
        let visuals = link_visuals("part_2", "part_2_box", &mesh, &materials, [0.5; 4]);
        assert_eq!(visuals.len(), 1);
        assert_eq!(visuals[0].stem, "part_2_visual");
        assert_eq!(visuals[0].faces, vec![0, 1, 2, 3]);
    }

    #[test]
    fn a_piece_of_one_triangle_is_drawn_with_the_largest() {
        let (mut mesh, materials) = two_quads();
        mesh.face_materials = Some(vec![1, 0, 0, 0]);
        let visuals = link_visuals("part_2", "part_2_box", &mesh, &materials, [0.5; 4]);
        assert_eq!(visuals.len(), 1, "{visuals:?}");
        assert_eq!(visuals[0].faces, vec![0, 1, 2, 3]);
    }

    #[test]
    fn the_textured_obj_keeps_only_its_vertices_with_flipped_v_and_its_mtl_names_the_texture() {
        let (mesh, materials) = two_quads();
        let visuals = link_visuals("part_2", "part_2_box", &mesh, &materials, [0.5; 4]);
        let (obj, mtl) = visual_files(&mesh, &visuals[0], DVec3::new(1.0, 0.0, 0.0));
        let obj = String::from_utf8(obj).expect("utf8");
        assert!(obj.contains("mtllib part_2_visual_m1.mtl\nusemtl part_2_box_m1_material\n"));
        assert_eq!(obj.matches("\nv ").count(), 4, "{obj}");
        assert!(
            obj.contains("v -1 0 0\nv 0 0 0\nv 0 1 0\nv -1 1 0\n"),
            "{obj}"
        );
        assert!(
            obj.contains("vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\n"),
            "{obj}"
        );
        assert!(obj.ends_with("f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"), "{obj}");
        let mtl = String::from_utf8(mtl.expect("textured piece has an MTL")).expect("utf8");
        assert!(mtl.contains("map_Kd texture_3.png"), "{mtl}");
        let (plain, none) = visual_files(&mesh, &visuals[1], DVec3::ZERO);
        assert!(none.is_none());
        let plain = String::from_utf8(plain).expect("utf8");
        assert!(
            !plain.contains("vt ") && !plain.contains("mtllib"),
            "{plain}"
        );
        assert!(plain.ends_with("f 1 2 3\nf 1 3 4\n"), "{plain}");
    }
}
