//! Checks every ingested part: finite coordinates, indices in range, and zero-area triangles
//! (dropped and counted; a part made only of them is an error).

use std::path::Path;

use uniphys_geometry::{DVec3, MeshAsset, TriMesh};

use crate::source::Session;
use crate::{IngestError, IngestResult};

/// A triangle is degenerate when its doubled area is at most this fraction of its longest
/// squared edge: collinear or coincident corners, independent of the unit.
const DEGENERATE_RATIO: f64 = 1e-12;

/// Checks the parts of `asset` read from `path`, drops zero-area triangles (adding their number
/// to the session) and drops parts without any triangle when the asset has no joints. Fails if
/// nothing is left.
pub(crate) fn sanitize(
    asset: &mut MeshAsset,
    path: &Path,
    session: &mut Session<'_>,
) -> IngestResult<()> {
    if asset.joints.is_empty() {
        asset.parts.retain(|p| !p.mesh.triangles.is_empty());
    }
    if asset.parts.is_empty() {
        return Err(IngestError::NoGeometry {
            path: path.to_path_buf(),
        });
    }
    for part in &mut asset.parts {
        let dropped = check_mesh(&mut part.mesh, path, &part.name)?;
        session.dropped_degenerate += dropped;
    }
    Ok(())
}

/// Checks one mesh, dropping degenerate triangles; returns how many were dropped.
fn check_mesh(mesh: &mut TriMesh, path: &Path, part: &str) -> IngestResult<usize> {
    if let Some(vertex) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(IngestError::NonFiniteVertex {
            path: path.to_path_buf(),
            part: part.to_owned(),
            vertex,
        });
    }
    let vertex_count = mesh.positions.len();
    for (triangle, tri) in mesh.triangles.iter().enumerate() {
        if let Some(&vertex) = tri.iter().find(|&&v| v as usize >= vertex_count) {
            return Err(IngestError::IndexOutOfRange {
                path: path.to_path_buf(),
                part: part.to_owned(),
                triangle,
                vertex: u64::from(vertex),
                vertex_count,
            });
        }
    }
    let keep: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&i| !is_degenerate(mesh.corners(i)))
        .collect();
    if keep.is_empty() {
        return Err(IngestError::Degenerate {
            path: path.to_path_buf(),
            part: part.to_owned(),
        });
    }
    let dropped = mesh.triangles.len() - keep.len();
    if dropped > 0 {
        *mesh = mesh.submesh(&keep);
    }
    mesh.validate().map_err(|source| IngestError::Geometry {
        path: path.to_path_buf(),
        part: part.to_owned(),
        source,
    })?;
    Ok(dropped)
}

/// Whether a triangle has (numerically) zero area.
pub(crate) fn is_degenerate([a, b, c]: [DVec3; 3]) -> bool {
    let longest = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    let doubled_area = (b - a).cross(c - a).length();
    longest == 0.0 || doubled_area <= DEGENERATE_RATIO * longest
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> TriMesh {
        TriMesh {
            positions,
            triangles,
            ..TriMesh::default()
        }
    }

    #[test]
    fn zero_area_triangles_are_dropped_and_counted() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(2.0, 0.0, 0.0)];
        // second triangle is collinear, third repeats a vertex
        let mut m = mesh(p, vec![[0, 1, 2], [0, 1, 3], [0, 0, 2]]);
        let dropped = check_mesh(&mut m, Path::new("f.obj"), "p").expect("ok");
        assert_eq!(dropped, 2);
        assert_eq!(m.triangle_count(), 1);
    }

    #[test]
    fn degeneracy_test_is_independent_of_scale() {
        let tri = |s: f64| [DVec3::ZERO, DVec3::X * s, DVec3::Y * s];
        for s in [1e-6, 1.0, 1e6] {
            assert!(!is_degenerate(tri(s)), "scale {s}");
        }
        assert!(is_degenerate([DVec3::ZERO, DVec3::X, DVec3::X * 3.0]));
    }

    #[test]
    fn nan_vertex_error_names_file_part_and_vertex() {
        let mut m = mesh(
            vec![DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Y],
            vec![[0, 1, 2]],
        );
        let err = check_mesh(&mut m, Path::new("f.obj"), "lid").expect_err("nan");
        let msg = err.to_string();
        assert!(
            msg.contains("f.obj") && msg.contains("\"lid\"") && msg.contains("vertex 1"),
            "{msg}"
        );
    }
}
