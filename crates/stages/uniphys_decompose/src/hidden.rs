//! Parts nobody can reach are not parts that move: a part whose surface is hidden inside the
//! object when it is closed (a cabinet's shelves and inner walls behind its doors, a dishwasher's
//! inner frame) cannot be grasped or operated, so it is structure and joins the largest part.
//!
//! Why: clustering cuts a body's inner panels off as parts of their own, and each one then costs
//! the body its share of the area and gets a joint downstream. Measured on the shared
//! PartNet-Mobility objects (`decompose-bench --partnet`): hidden parts were body panels in every
//! case but the inner skin of a door drawn flush behind its outer skin, which the probe's gap
//! keeps exposed.

use uniphys_geometry::{ExposureProbe, TriMesh, sample_points};

use crate::part_faces::PartFaces;

/// Tuning of [`merge_hidden_parts`].
#[derive(Debug, Clone, PartialEq)]
pub struct HiddenOptions {
    /// Rays per sample, spread over the sphere (default 24).
    pub directions: usize,
    /// Surfaces nearer than this share of the bounds diagonal do not hide a point: the other
    /// face of a sheet, a skin drawn flush against another (default 0.005).
    pub skip_rel: f64,
    /// Samples per part (default 200).
    pub samples: usize,
    /// A part with fewer of its samples exposed than this share is hidden (default 0.05).
    pub exposed_share_max: f64,
    /// Parts below this share of the total area are left alone (default 1e-4).
    pub area_fraction_min: f64,
}

impl Default for HiddenOptions {
    fn default() -> Self {
        Self {
            directions: 24,
            skip_rel: 0.005,
            samples: 200,
            exposed_share_max: 0.05,
            area_fraction_min: 1e-4,
        }
    }
}

/// Merges every part but the largest whose surface cannot be reached from outside into the
/// largest part. Returns the new labels (numbered by smallest face), their count and how many
/// parts were merged.
#[must_use]
pub fn merge_hidden_parts(
    mesh: &TriMesh,
    face_part: &[u32],
    options: &HiddenOptions,
) -> (Vec<u32>, usize, usize) {
    let parts = PartFaces::of(mesh, face_part);
    let unchanged = || (face_part.to_vec(), parts.count(), 0);
    let Some(largest) = parts.largest().filter(|_| parts.count() >= 2) else {
        return unchanged();
    };
    let Some(probe) = ExposureProbe::new(mesh, options.directions, options.skip_rel) else {
        return unchanged();
    };
    let hidden: Vec<usize> = (0..parts.count())
        .filter(|&p| p != largest && parts.area_m2[p] >= options.area_fraction_min * parts.total_m2)
        .filter(|&p| is_hidden(mesh, &parts.faces_of[p], &probe, p as u64, options))
        .collect();
    if hidden.is_empty() {
        return unchanged();
    }
    let (labels, count) = parts.joined_into(face_part, &hidden, largest);
    (labels, count, hidden.len())
}

/// Whether fewer than the allowed share of the part's samples see outside. Stops as soon as the
/// answer is known.
fn is_hidden(
    mesh: &TriMesh,
    faces: &[usize],
    probe: &ExposureProbe,
    seed: u64,
    options: &HiddenOptions,
) -> bool {
    let points = sample_points(&mesh.submesh(faces), options.samples, seed);
    if points.is_empty() {
        return false;
    }
    let allowed = (options.exposed_share_max * points.len() as f64).ceil() as usize;
    let mut exposed = 0;
    for &p in &points {
        if probe.is_exposed(p) {
            exposed += 1;
            if exposed >= allowed {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;

    /// A closed cabinet shell (part 0), a shelf inside it (part 1) and a knob on its front
    /// (part 2).
    fn cabinet() -> (TriMesh, Vec<u32>) {
        let shell = TriMesh::cuboid(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 0.6, 1.0));
        let shelf = TriMesh::cuboid(DVec3::new(0.05, 0.05, 0.48), DVec3::new(0.95, 0.55, 0.5));
        let knob = TriMesh::cuboid(DVec3::new(0.45, -0.05, 0.45), DVec3::new(0.55, 0.0, 0.55));
        let mut labels = Vec::new();
        for (i, m) in [&shell, &shelf, &knob].into_iter().enumerate() {
            labels.extend(std::iter::repeat_n(i as u32, m.triangle_count()));
        }
        (TriMesh::merge([&shell, &shelf, &knob]), labels)
    }

    #[test]
    fn a_shelf_closed_inside_joins_the_body_and_a_knob_outside_stays() {
        let (mesh, labels) = cabinet();
        let (merged, count, hidden) = merge_hidden_parts(&mesh, &labels, &HiddenOptions::default());
        assert_eq!((count, hidden), (2, 1));
        let shelf_faces = 12..24;
        assert!(shelf_faces.clone().all(|f| merged[f] == merged[0]));
        assert!((24..36).all(|f| merged[f] != merged[0]));
    }

    #[test]
    fn nothing_is_hidden_in_an_open_cabinet() {
        // Without its front wall the shelf is seen from the front.
        let (mesh, labels) = cabinet();
        let keep: Vec<usize> = (0..mesh.triangle_count())
            .filter(|&f| !(labels[f] == 0 && mesh.face_normal(f).y < -0.5))
            .collect();
        let open = mesh.submesh(&keep);
        let open_labels: Vec<u32> = keep.iter().map(|&f| labels[f]).collect();
        let (_, count, hidden) = merge_hidden_parts(&open, &open_labels, &HiddenOptions::default());
        assert_eq!((count, hidden), (3, 0));
    }
}
