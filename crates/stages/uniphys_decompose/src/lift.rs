//! Lifting a view's 2D labels to mesh faces (reference §3.2): each face goes to the label with
//! the most pixels on it, then labels that mostly lie on faces won by others are dissolved.

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_render::{Camera, FaceIdImage};

use crate::segment::LabelMap;
use crate::views::PixelRays;
use crate::{DecomposeError, DecomposeResult};

/// Sorted, distinct face indices of the merged mesh.
pub type FaceSet = Vec<u32>;

/// Options of [`lift_labels`] and [`lift_view`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftOptions {
    /// A label is dissolved when more than this fraction of its area lies on faces won by other
    /// labels (default 0.5, the reference's "area merge").
    pub dissolve_fraction: f64,
    /// [`lift_view`]: faces without a pixel vote by their centroid (default true).
    pub subpixel_faces: bool,
    /// Depth tolerance of a centroid vote in pixel footprints at its depth (default 2.0) ...
    pub subpixel_depth_px: f64,
    /// ... or as a fraction of the mesh diagonal, whichever is larger (default 0.005).
    pub subpixel_depth_fraction: f64,
}

impl Default for LiftOptions {
    fn default() -> Self {
        Self {
            dissolve_fraction: 0.5,
            subpixel_faces: true,
            subpixel_depth_px: 2.0,
            subpixel_depth_fraction: 0.005,
        }
    }
}

/// Votes of one label on one face.
#[derive(Debug, Clone, Copy)]
struct Vote {
    face: u32,
    label: u32,
    pixels: u32,
}

/// The face sets of one view's labels.
///
/// `face_ids` holds 0 for background and `i + 1` for face `i` (as a face-ID render); `labels`
/// holds -1 for ignored pixels. Every face with labelled pixels goes to the label with the most
/// pixels on it (ties: the smaller label). Areas are surface areas, not pixel counts: a label's
/// pixels on a face stand for `face_area * (its pixels on the face) / (labelled pixels on the
/// face)`, so foreshortened or finely tessellated surfaces are not under- or over-weighted.
/// Labels are then visited from the smallest area to the largest (ties: smaller label first);
/// one with more than [`LiftOptions::dissolve_fraction`] of its area on faces currently won by
/// other labels is dissolved, its faces going to the label that won most of that area (ties: the
/// smaller label). The result lists the non-empty labels in increasing label order.
pub fn lift_labels(
    face_ids: &[u32],
    labels: &[i32],
    face_area_m2: &[f64],
    options: &LiftOptions,
) -> DecomposeResult<Vec<FaceSet>> {
    if face_ids.len() != labels.len() {
        return Err(DecomposeError::InvalidInput(format!(
            "{} face-ID pixels but {} labels",
            face_ids.len(),
            labels.len()
        )));
    }
    Ok(lift_keys(
        pixel_keys(face_ids, labels, face_area_m2.len()),
        face_area_m2,
        options,
    ))
}

/// Like [`lift_labels`] for a rendered view, and faces too small to own a pixel are not lost:
/// with [`LiftOptions::subpixel_faces`], each face without pixels whose centroid projects onto
/// a labelled pixel at that pixel's depth (within [`LiftOptions::subpixel_depth_px`] pixel
/// footprints, or [`LiftOptions::subpixel_depth_fraction`] of the mesh diagonal if larger) and
/// whose normal is within 45 degrees of that pixel's (either side) votes once for that pixel's
/// label; the normal test keeps faces just behind a silhouette edge out. Without this, a finely
/// tessellated part seen from two views gives two sparse, barely overlapping face samples that
/// cross-view merging cannot match.
pub fn lift_view(
    mesh: &TriMesh,
    camera: &Camera,
    image: &FaceIdImage,
    labels: &LabelMap,
    face_area_m2: &[f64],
    options: &LiftOptions,
) -> DecomposeResult<Vec<FaceSet>> {
    if image.face.len() != labels.labels.len() || image.depth_m.len() != image.face.len() {
        return Err(DecomposeError::InvalidInput(format!(
            "{} face-ID pixels, {} depths, {} labels",
            image.face.len(),
            image.depth_m.len(),
            labels.labels.len()
        )));
    }
    let face_count = face_area_m2.len().min(mesh.triangle_count());
    let mut keys = pixel_keys(&image.face, &labels.labels, face_count);
    if options.subpixel_faces {
        let mut has_pixel = vec![false; face_count];
        for &id in &image.face {
            if let Some(seen) = (id as usize)
                .checked_sub(1)
                .and_then(|f| has_pixel.get_mut(f))
            {
                *seen = true;
            }
        }
        let (w, h) = (image.width_px, image.height_px);
        let rays = PixelRays::new(camera);
        let floor_m = options.subpixel_depth_fraction * mesh.bounds().diagonal();
        for (face, _) in has_pixel.iter().enumerate().filter(|&(_, &seen)| !seen) {
            let [a, b, c] = mesh.corners(face);
            let Some((x_px, y_px, depth_m)) = rays.project((a + b + c) / 3.0) else {
                continue;
            };
            if !(0.0..f64::from(w)).contains(&x_px) || !(0.0..f64::from(h)).contains(&y_px) {
                continue;
            }
            let k = y_px as usize * w as usize + x_px as usize;
            let label = labels.labels[k];
            let tolerance_m =
                (options.subpixel_depth_px * rays.footprint_per_m * depth_m).max(floor_m);
            let seen_normal = image.normal_world.get(k).map_or(DVec3::ZERO, |n| {
                DVec3::new(f64::from(n[0]), f64::from(n[1]), f64::from(n[2]))
            });
            let aligned = mesh.face_normal(face).dot(seen_normal).abs() >= SUBPIXEL_NORMAL_COS;
            if label >= 0 && aligned && (f64::from(image.depth_m[k]) - depth_m).abs() <= tolerance_m
            {
                keys.push(vote_key(face, label));
            }
        }
    }
    Ok(lift_keys(keys, face_area_m2, options))
}

/// |cos| of the largest angle between a sub-pixel face's normal and the visible normal at its
/// centroid's pixel (45 degrees).
const SUBPIXEL_NORMAL_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn vote_key(face: usize, label: i32) -> u64 {
    ((face as u64) << 32) | u64::from(label.unsigned_abs())
}

/// One `face << 32 | label` key per labelled pixel on a face below `face_count`.
fn pixel_keys(face_ids: &[u32], labels: &[i32], face_count: usize) -> Vec<u64> {
    face_ids
        .iter()
        .zip(labels)
        .filter(|&(&f, &l)| f > 0 && (f as usize) <= face_count && l >= 0)
        .map(|(&f, &l)| vote_key(f as usize - 1, l))
        .collect()
}

/// The lifting itself, from one key per vote.
fn lift_keys(mut keys: Vec<u64>, face_area_m2: &[f64], options: &LiftOptions) -> Vec<FaceSet> {
    let face_count = face_area_m2.len();
    keys.sort_unstable();
    let mut votes = run_lengths(&keys);
    if votes.is_empty() {
        return Vec::new();
    }
    // Labels renumbered densely in their order (a segmenter may use any values, e.g. i32::MAX);
    // the order, and with it the tie rule below, is unchanged.
    let mut labels: Vec<u32> = votes.iter().map(|v| v.label).collect();
    labels.sort_unstable();
    labels.dedup();
    for v in &mut votes {
        v.label = u32::try_from(labels.partition_point(|&l| l < v.label)).unwrap_or(u32::MAX);
    }
    let label_count = labels.len();

    // Winner and labelled pixel total per face; votes are sorted by face, then label.
    let mut owner = vec![u32::MAX; face_count];
    let mut face_pixels = vec![0u32; face_count];
    let mut best = vec![0u32; face_count];
    for v in &votes {
        let f = v.face as usize;
        face_pixels[f] += v.pixels;
        // Labels arrive in increasing order, so `>` keeps the smaller label on ties.
        if owner[f] == u32::MAX || v.pixels > best[f] {
            owner[f] = v.label;
            best[f] = v.pixels;
        }
    }
    let weight = |v: &Vote| {
        let f = v.face as usize;
        face_area_m2[f] * f64::from(v.pixels) / f64::from(face_pixels[f].max(1))
    };

    // Votes grouped by label, and each label's faces.
    let mut by_label: Vec<Vec<Vote>> = vec![Vec::new(); label_count];
    let mut total = vec![0.0f64; label_count];
    for v in &votes {
        by_label[v.label as usize].push(*v);
        total[v.label as usize] += weight(v);
    }
    let mut owned: Vec<Vec<u32>> = vec![Vec::new(); label_count];
    for (f, &o) in owner.iter().enumerate() {
        if o != u32::MAX {
            owned[o as usize].push(u32::try_from(f).unwrap_or(u32::MAX));
        }
    }

    let mut order: Vec<usize> = (0..label_count).filter(|&l| total[l] > 0.0).collect();
    order.sort_by(|&a, &b| total[a].total_cmp(&total[b]).then(a.cmp(&b)));
    let mut received = vec![0.0f64; label_count];
    for label in order {
        if owned[label].is_empty() {
            continue;
        }
        received.fill(0.0);
        let mut outside = 0.0;
        for v in &by_label[label] {
            let o = owner[v.face as usize];
            if o as usize != label {
                let w = weight(v);
                outside += w;
                received[o as usize] += w;
            }
        }
        if outside <= options.dissolve_fraction * total[label] {
            continue;
        }
        let mut target = usize::MAX;
        for (other, &w) in received.iter().enumerate() {
            if w > 0.0 && (target == usize::MAX || w > received[target]) {
                target = other;
            }
        }
        if target == usize::MAX {
            continue;
        }
        let moved = std::mem::take(&mut owned[label]);
        for &f in &moved {
            owner[f as usize] = u32::try_from(target).unwrap_or(u32::MAX);
        }
        owned[target].extend(moved);
    }

    owned
        .into_iter()
        .filter(|faces| !faces.is_empty())
        .map(|mut faces| {
            faces.sort_unstable();
            faces
        })
        .collect()
}

/// Counts of equal `face << 32 | label` keys in a sorted slice.
fn run_lengths(sorted_keys: &[u64]) -> Vec<Vote> {
    let mut votes: Vec<Vote> = Vec::new();
    for &key in sorted_keys {
        let face = (key >> 32) as u32;
        let label = (key & 0xFFFF_FFFF) as u32;
        match votes.last_mut() {
            Some(v) if v.face == face && v.label == label => v.pixels += 1,
            _ => votes.push(Vote {
                face,
                label,
                pixels: 1,
            }),
        }
    }
    votes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pixels of (face index, label, count), as flat face-ID and label buffers.
    fn pixels(runs: &[(Option<u32>, i32, usize)]) -> (Vec<u32>, Vec<i32>) {
        let mut faces = Vec::new();
        let mut labels = Vec::new();
        for &(face, label, n) in runs {
            faces.extend(std::iter::repeat_n(face.map_or(0, |f| f + 1), n));
            labels.extend(std::iter::repeat_n(label, n));
        }
        (faces, labels)
    }

    #[test]
    fn each_face_goes_to_the_label_with_most_pixels() {
        let (faces, labels) = pixels(&[
            (Some(0), 0, 5),
            (Some(0), 1, 3),
            (Some(1), 1, 4),
            (Some(1), 0, 1),
            (Some(2), 0, 2),
            (Some(2), 1, 2),  // tie: the smaller label
            (None, 1, 50),    // background pixels never vote
            (Some(3), -1, 9), // ignored pixels never vote
        ]);
        // Dissolution off: only the vote is under test.
        let vote_only = LiftOptions {
            dissolve_fraction: 1.0,
            ..LiftOptions::default()
        };
        let sets = lift_labels(&faces, &labels, &[1.0; 5], &vote_only).unwrap_or_default();
        assert_eq!(sets, vec![vec![0, 2], vec![1]]);
    }

    #[test]
    fn a_label_mostly_on_faces_won_by_others_is_dissolved_into_its_main_neighbour() {
        // Label 2 wins face 3 but most of its area lies on faces 0 and 1 (won by 0) and a little
        // on face 2 (won by 1): 0.5 + 0.5 + 1/6 of 2 + 1/6 face areas, 0.54 > 0.5, so it is
        // dissolved and face 3 goes to label 0, which won most of that area.
        let (faces, labels) = pixels(&[
            (Some(0), 0, 10),
            (Some(0), 2, 10),
            (Some(1), 0, 10),
            (Some(1), 2, 10),
            (Some(2), 1, 10),
            (Some(2), 2, 2),
            (Some(3), 2, 4),
        ]);
        let area = [1.0; 4];
        let sets = lift_labels(&faces, &labels, &area, &LiftOptions::default()).unwrap_or_default();
        assert_eq!(sets, vec![vec![0, 1, 3], vec![2]]);
        // With a threshold above its outside share label 2 survives.
        let keep = LiftOptions {
            dissolve_fraction: 0.6,
            ..LiftOptions::default()
        };
        let sets = lift_labels(&faces, &labels, &area, &keep).unwrap_or_default();
        assert_eq!(sets, vec![vec![0, 1], vec![2], vec![3]]);
    }

    #[test]
    fn dissolution_weighs_surface_area_not_pixels() {
        // Label 1 has 8 of its 12 pixels on face 0 (won by label 0) and 4 on face 1, which it
        // owns: by pixel count 2/3 would lie outside. By area it covers 8/28 of face 0 and all
        // of face 1: with equal face areas 0.22 of its area is outside and it survives; when
        // face 0 is ten times larger, 0.74 is outside and it is dissolved into label 0.
        let (faces, labels) = pixels(&[(Some(0), 0, 20), (Some(0), 1, 8), (Some(1), 1, 4)]);
        let options = LiftOptions::default();
        let equal = lift_labels(&faces, &labels, &[1.0, 1.0], &options).unwrap_or_default();
        assert_eq!(equal, vec![vec![0], vec![1]]);
        let big_face_0 = lift_labels(&faces, &labels, &[10.0, 1.0], &options).unwrap_or_default();
        assert_eq!(big_face_0, vec![vec![0, 1]]);
    }

    #[test]
    fn mismatched_buffers_are_an_error() {
        let result = lift_labels(&[1, 2], &[0], &[1.0, 1.0], &LiftOptions::default());
        assert!(matches!(result, Err(DecomposeError::InvalidInput(_))));
    }

    #[test]
    fn sparse_label_values_lift_like_dense_ones() {
        let (faces, dense) = pixels(&[(Some(0), 1, 5), (Some(1), 2, 5), (Some(2), 2, 3)]);
        let sparse: Vec<i32> = dense
            .iter()
            .map(|&l| if l == 2 { i32::MAX } else { l })
            .collect();
        let areas = [1.0; 3];
        let options = LiftOptions::default();
        let expected = lift_labels(&faces, &dense, &areas, &options).unwrap();
        assert_eq!(expected, vec![vec![0], vec![1, 2]]);
        assert_eq!(
            lift_labels(&faces, &sparse, &areas, &options).unwrap(),
            expected
        );
    }
}

#[cfg(test)]
mod view_tests {
    use uniphys_geometry::DVec3;
    use uniphys_render::{orbit_cameras, render_face_ids};

    use super::*;
    use crate::segment::test_meshes::fine_cuboid;

    #[test]
    fn faces_smaller_than_a_pixel_are_lifted_by_their_centroid_and_hidden_ones_are_not() {
        // 19,200 triangles in a 64 px view: most own no pixel.
        let mesh = fine_cuboid(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.6), 40);
        let camera = orbit_cameras(&mesh.bounds(), 8, 64, 64)[0];
        let image = render_face_ids(&mesh, &camera);
        let labels = LabelMap {
            width_px: 64,
            height_px: 64,
            labels: image
                .face
                .iter()
                .map(|&f| if f > 0 { 0 } else { -1 })
                .collect(),
        };
        let area: Vec<f64> = (0..mesh.triangle_count())
            .map(|f| mesh.face_area(f))
            .collect();
        let facing = |f: usize| {
            let [a, b, c] = mesh.corners(f);
            mesh.face_normal(f).dot(camera.eye_m - (a + b + c) / 3.0) > 0.0
        };
        let front = (0..mesh.triangle_count()).filter(|&f| facing(f)).count();
        let lift = |subpixel_faces: bool| {
            let options = LiftOptions {
                subpixel_faces,
                ..LiftOptions::default()
            };
            match lift_view(&mesh, &camera, &image, &labels, &area, &options) {
                Ok(mut sets) if sets.len() == 1 => sets.remove(0),
                other => panic!("one set expected: {other:?}"),
            }
        };
        let pixels_only = lift(false);
        let with_centroids = lift(true);
        assert!(
            pixels_only.len() * 2 < front,
            "{} of {front}",
            pixels_only.len()
        );
        // Faces along the silhouette may project just off the object or onto the other side.
        assert!(
            with_centroids.len() * 100 >= front * 95,
            "{} of {front}",
            with_centroids.len()
        );
        assert!(with_centroids.iter().all(|&f| facing(f as usize)));
        assert!(
            pixels_only
                .iter()
                .all(|f| with_centroids.binary_search(f).is_ok())
        );
    }
}
