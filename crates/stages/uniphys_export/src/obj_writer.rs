//! Wavefront OBJ output of the collision hulls: one object per file, no groups and no materials
//! (MuJoCo wants one mesh per file). The visual meshes are written by [`crate::visuals`].

use std::fmt::Write as _;

use uniphys_geometry::{DVec3, TriMesh};

use crate::xml::coord;

/// Writes `mesh` translated by `-origin` (i.e. into a frame located at `origin`), positions and
/// faces only: simulators take the colour from the model file.
pub(crate) fn write_obj(mesh: &TriMesh, origin: DVec3) -> Vec<u8> {
    let mut s = String::with_capacity(mesh.positions.len() * 32 + mesh.triangles.len() * 24);
    s.push_str("# written by uniphys\n");
    for p in &mesh.positions {
        let q = *p - origin;
        let _ = writeln!(s, "v {} {} {}", coord(q.x), coord(q.y), coord(q.z));
    }
    for t in &mesh.triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
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
