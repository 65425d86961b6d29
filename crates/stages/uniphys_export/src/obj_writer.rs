//! Wavefront OBJ and MTL lines as the export writes them (the part files, the visual meshes and
//! the collision hulls), and the hulls' files: one object per file, no groups and no materials
//! (MuJoCo wants one mesh per file). The visual meshes are written by [`crate::visuals`].

use std::fmt::Write as _;

use uniphys_geometry::{DVec3, TriMesh};

use crate::visuals::texture_file;
use crate::xml::{coord, short_f32};

/// Appends the vertex line of `p`.
pub(crate) fn vertex_line(s: &mut String, p: DVec3) {
    let _ = writeln!(s, "v {} {} {}", coord(p.x), coord(p.y), coord(p.z));
}

/// Appends the texture coordinate line of a glTF `[u, v]` (v down the image; OBJ's runs up).
pub(crate) fn texcoord_line(s: &mut String, [u, v]: [f32; 2]) {
    let _ = writeln!(s, "vt {} {}", short_f32(u), short_f32(1.0 - v));
}

/// Appends the face line of triangle `t` (zero-based vertices); `textured`, each corner's
/// texture coordinate has its vertex's number.
pub(crate) fn face_line(s: &mut String, t: [u32; 3], textured: bool) {
    let [a, b, c] = t.map(|v| v + 1);
    if textured {
        let _ = writeln!(s, "f {a}/{a} {b}/{b} {c}/{c}");
    } else {
        let _ = writeln!(s, "f {a} {b} {c}");
    }
}

/// Appends an MTL material `name`: its linear colour and opacity and, if it has one, its
/// base-colour texture's file.
pub(crate) fn mtl_material(s: &mut String, name: &str, rgba: [f32; 4], texture: Option<usize>) {
    let [r, g, b, a] = rgba.map(short_f32);
    let _ = writeln!(s, "newmtl {name}\nKd {r} {g} {b}\nd {a}");
    if let Some(t) = texture {
        let _ = writeln!(s, "map_Kd {}", texture_file(t));
    }
}

/// Writes `mesh` translated by `-origin` (i.e. into a frame located at `origin`), positions and
/// faces only: simulators take the colour from the model file.
pub(crate) fn write_obj(mesh: &TriMesh, origin: DVec3) -> Vec<u8> {
    let mut s = String::with_capacity(mesh.positions.len() * 32 + mesh.triangles.len() * 24);
    s.push_str("# written by uniphys\n");
    for p in &mesh.positions {
        vertex_line(&mut s, *p - origin);
    }
    for t in &mesh.triangles {
        face_line(&mut s, *t, false);
    }
    s.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_has_one_based_faces_and_shifted_vertices() {
        let mesh = TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 2]]).unwrap();
        let text = String::from_utf8(write_obj(&mesh, DVec3::new(1.0, 0.0, 0.0))).unwrap();
        assert!(!text.contains("mtllib"));
        assert!(text.contains("v -1 0 0\nv 0 0 0\nv -1 1 0\n"));
        assert!(text.ends_with("f 1 2 3\n"));
    }
}
