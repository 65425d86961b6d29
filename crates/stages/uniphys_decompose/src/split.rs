//! Applying a face-to-part map (from [`crate::Decomposition`] or a stored `face_parts.json`) to
//! the asset it was computed on.

use uniphys_geometry::{MeshAsset, MeshPart};

use crate::{DecomposeError, DecomposeResult};

/// `asset` with its parts replaced by the parts of `face_part` (one entry per face of
/// `asset.merged()`, values `0..n`, every part non-empty). Materials and textures are kept;
/// declared joints are dropped, since they name the input's parts. Parts are named `part_<i>`.
///
/// # Errors
/// [`DecomposeError::InvalidInput`] if the map does not fit the asset.
pub fn split_asset(asset: &MeshAsset, face_part: &[u32]) -> DecomposeResult<MeshAsset> {
    let mesh = asset.merged();
    if face_part.len() != mesh.triangle_count() {
        return Err(DecomposeError::InvalidInput(format!(
            "the face-to-part map has {} entries but the asset has {} faces (was it computed on \
             this asset with the same reader options?)",
            face_part.len(),
            mesh.triangle_count()
        )));
    }
    let part_count = face_part.iter().max().map_or(0, |&p| p as usize + 1);
    if part_count > face_part.len() {
        return Err(DecomposeError::InvalidInput(format!(
            "the face-to-part map names part {} but {} faces can make at most {} parts",
            part_count - 1,
            face_part.len(),
            face_part.len()
        )));
    }
    let mut faces = vec![Vec::new(); part_count];
    for (face, &part) in face_part.iter().enumerate() {
        faces[part as usize].push(face);
    }
    if let Some(empty) = faces.iter().position(Vec::is_empty) {
        return Err(DecomposeError::InvalidInput(format!(
            "the face-to-part map skips part {empty} (parts must be numbered 0..{part_count} without gaps)"
        )));
    }
    let parts = faces
        .iter()
        .enumerate()
        .map(|(i, faces)| MeshPart {
            name: format!("part_{i}"),
            mesh: mesh.submesh(faces),
        })
        .collect();
    Ok(MeshAsset {
        parts,
        materials: asset.materials.clone(),
        textures: asset.textures.clone(),
        joints: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::{DVec3, TriMesh};

    use super::*;

    fn two_boxes() -> MeshAsset {
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::new(2.0, 0.0, 0.0), DVec3::new(3.0, 1.0, 1.0));
        MeshAsset {
            parts: vec![MeshPart {
                name: "all".into(),
                mesh: TriMesh::merge([&a, &b]),
            }],
            materials: Vec::new(),
            textures: Vec::new(),
            joints: Vec::new(),
        }
    }

    #[test]
    fn splits_by_the_map_and_refuses_maps_that_do_not_fit() {
        let asset = two_boxes();
        let faces = asset.triangle_count();
        let map: Vec<u32> = (0..faces).map(|f| u32::from(f >= faces / 2)).collect();
        let split = split_asset(&asset, &map).unwrap();
        assert_eq!(split.parts.len(), 2);
        assert_eq!(split.parts[0].mesh.triangle_count(), faces / 2);
        assert!(split.parts[1].mesh.bounds().min.x >= 2.0 - 1e-12);
        assert!(split_asset(&asset, &map[1..]).is_err());
        let gap: Vec<u32> = map.iter().map(|p| p * 2).collect();
        assert!(split_asset(&asset, &gap).is_err());
        // A corrupt map naming a huge part is refused before anything is allocated for it.
        let mut huge = map.clone();
        huge[0] = u32::MAX;
        let message = split_asset(&asset, &huge).unwrap_err().to_string();
        assert!(message.contains("at most"), "{message}");
    }
}
