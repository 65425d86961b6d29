//! The faces, areas and main materials of each part of a face-to-part map, for the steps that
//! join whole parts ([`crate::hidden`], [`crate::layers`], [`crate::tops`],
//! [`crate::small_parts`]).

use uniphys_geometry::TriMesh;

use crate::candidates::relabel_by_first_face;

/// Each part's faces and area.
pub(crate) struct PartFaces {
    /// The faces of each part, by part index.
    pub(crate) faces_of: Vec<Vec<usize>>,
    /// The area of each part, square metres.
    pub(crate) area_m2: Vec<f64>,
    /// The area of the whole mesh, square metres.
    pub(crate) total_m2: f64,
}

impl PartFaces {
    /// The parts of `face_part` (labels `0..n`) on `mesh`.
    pub(crate) fn of(mesh: &TriMesh, face_part: &[u32]) -> Self {
        let parts = face_part.iter().max().map_or(0, |&m| m as usize + 1);
        let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); parts];
        let mut area_m2 = vec![0.0f64; parts];
        for (f, &p) in face_part.iter().enumerate() {
            faces_of[p as usize].push(f);
            area_m2[p as usize] += mesh.face_area(f);
        }
        let total_m2 = area_m2.iter().sum();
        Self {
            faces_of,
            area_m2,
            total_m2,
        }
    }

    /// The material covering most of each part's area (smallest id on ties), from one material
    /// id per face (missing ids count as 0).
    pub(crate) fn main_materials(&self, mesh: &TriMesh, face_material: &[u32]) -> Vec<u32> {
        main_materials(mesh, &self.faces_of, face_material)
    }

    /// How many parts there are.
    pub(crate) fn count(&self) -> usize {
        self.faces_of.len()
    }

    /// The part with the most area (the last of equals).
    pub(crate) fn largest(&self) -> Option<usize> {
        (0..self.count()).max_by(|&a, &b| self.area_m2[a].total_cmp(&self.area_m2[b]))
    }

    /// `face_part` with the faces of `parts` moved to `target`, renumbered by smallest face, and
    /// the new part count.
    pub(crate) fn joined_into(
        &self,
        face_part: &[u32],
        parts: &[usize],
        target: usize,
    ) -> (Vec<u32>, usize) {
        let target = u32::try_from(target).unwrap_or(u32::MAX);
        let mut labels = face_part.to_vec();
        for &p in parts {
            for &f in &self.faces_of[p] {
                labels[f] = target;
            }
        }
        relabel_by_first_face(&labels)
    }
}

/// The material covering most of the area of each set of faces (smallest id on ties), from one
/// material id per face (missing ids count as 0).
pub(crate) fn main_materials(
    mesh: &TriMesh,
    faces_of: &[Vec<usize>],
    face_material: &[u32],
) -> Vec<u32> {
    faces_of
        .iter()
        .map(|fs| {
            let mut by: std::collections::BTreeMap<u32, f64> = std::collections::BTreeMap::new();
            for &f in fs {
                let m = face_material.get(f).copied().unwrap_or(0);
                *by.entry(m).or_insert(0.0) += mesh.face_area(f);
            }
            by.iter()
                .fold(None, |best: Option<(u32, f64)>, (&m, &a)| match best {
                    Some((_, b)) if b >= a => best,
                    _ => Some((m, a)),
                })
                .map_or(0, |(m, _)| m)
        })
        .collect()
}
