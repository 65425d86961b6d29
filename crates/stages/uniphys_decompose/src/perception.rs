//! The perception half of the stage: render the views, segment each, lift the labels to faces,
//! merge them across views and estimate the part-count prior.

use uniphys_geometry::TriMesh;

use crate::consensus::{ConsensusOptions, merge_view_masks};
use crate::lift::{FaceSet, LiftOptions, lift_view};
use crate::prior::{K_PRIOR_COVERAGE, k_prior};
use crate::segment::{Segmenter, ViewImage};
use crate::views::{ViewOptions, ViewSet, map_views, render_views_on};
use crate::{DecomposeError, DecomposeResult};

/// Options of [`perceive`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PerceptionOptions {
    /// Views to render.
    pub views: ViewOptions,
    /// Lifting of labels to faces.
    pub lift: LiftOptions,
    /// Cross-view merging.
    pub consensus: ConsensusOptions,
    /// Coverage that sets the part-count prior (default [`K_PRIOR_COVERAGE`], 0.99).
    pub k_coverage: f64,
    /// Threads rendering, segmenting and lifting views (default 1; views are independent, the
    /// result does not depend on the thread count).
    pub threads: usize,
}

impl Default for PerceptionOptions {
    fn default() -> Self {
        Self {
            views: ViewOptions::default(),
            lift: LiftOptions::default(),
            consensus: ConsensusOptions::default(),
            k_coverage: K_PRIOR_COVERAGE,
            threads: 1,
        }
    }
}

/// What the views say about the parts.
#[derive(Debug, Clone)]
pub struct Perception {
    /// The rendered views.
    pub views: ViewSet,
    /// Per view, the face set of every region lifted to the mesh (disjoint within a view).
    pub per_view: Vec<Vec<FaceSet>>,
    /// The masks merged across views: disjoint, largest area first.
    pub merged: Vec<FaceSet>,
    /// Per face, whether any view shows at least one of its pixels or lifted it to a mask (a
    /// face smaller than a pixel, by its centroid).
    pub visible_faces: Vec<bool>,
    /// K0, the number of largest merged masks covering more than the coverage of their area.
    pub k_prior: usize,
    /// Who segmented the views.
    pub provider: String,
}

/// Renders `mesh`, segments every view with `segmenter`, lifts and merges the regions and
/// estimates the part-count prior. Deterministic for a deterministic segmenter.
///
/// `face_rgba` and `face_material` have one entry per face (`face_material` may be empty when
/// materials are unknown). Errors when no face is visible, a segmenter fails or returns a map of
/// the wrong size, or no region lifts to any face.
pub fn perceive(
    mesh: &TriMesh,
    face_rgba: &[[u8; 4]],
    face_material: &[u32],
    segmenter: &dyn Segmenter,
    options: &PerceptionOptions,
) -> DecomposeResult<Perception> {
    let faces = mesh.triangle_count();
    if !face_material.is_empty() && face_material.len() != faces {
        return Err(DecomposeError::InvalidInput(format!(
            "{} face materials for {faces} faces",
            face_material.len()
        )));
    }
    let views = render_views_on(mesh, face_rgba, &options.views, options.threads)?;
    let mut visible_faces = vec![false; faces];
    for image in &views.face_ids {
        for &id in &image.face {
            if let Some(seen) = (id as usize)
                .checked_sub(1)
                .and_then(|f| visible_faces.get_mut(f))
            {
                *seen = true;
            }
        }
    }
    if !visible_faces.contains(&true) {
        return Err(DecomposeError::NothingVisible);
    }
    let face_area_m2: Vec<f64> = (0..faces).map(|f| mesh.face_area(f)).collect();

    let lift_view = |k: usize| -> DecomposeResult<Vec<FaceSet>> {
        let image = &views.face_ids[k];
        let view = ViewImage {
            index: k,
            camera: &views.cameras[k],
            face_ids: image,
            colour: &views.colour[k],
            face_material,
        };
        let labels = segmenter.segment(&view)?;
        if (labels.width_px, labels.height_px) != (image.width_px, image.height_px)
            || labels.labels.len() != image.face.len()
        {
            return Err(DecomposeError::Segmentation {
                view: k,
                message: format!(
                    "label map of {} x {} px ({} labels) for a {} x {} px view",
                    labels.width_px,
                    labels.height_px,
                    labels.labels.len(),
                    image.width_px,
                    image.height_px
                ),
            });
        }
        lift_view(
            mesh,
            &views.cameras[k],
            image,
            &labels,
            &face_area_m2,
            &options.lift,
        )
    };
    let per_view = map_views(views.cameras.len(), options.threads, &lift_view)?;
    for &f in per_view.iter().flatten().flatten() {
        if let Some(seen) = visible_faces.get_mut(f as usize) {
            *seen = true;
        }
    }

    let merged = merge_view_masks(&per_view, &face_area_m2, &options.consensus);
    if merged.is_empty() {
        return Err(DecomposeError::NoMasks);
    }
    let k_prior = k_prior(&merged, &face_area_m2, options.k_coverage);
    Ok(Perception {
        views,
        per_view,
        merged,
        visible_faces,
        k_prior,
        provider: segmenter.provider(),
    })
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;
    use crate::segment::test_meshes::{CUBOID_FACES, box_with_inset_lid};
    use crate::segment::{BuiltinSegmenter, LabelMap};

    fn small_views() -> PerceptionOptions {
        PerceptionOptions {
            views: ViewOptions {
                count: 8,
                resolution_px: 128,
            },
            ..PerceptionOptions::default()
        }
    }

    fn perceive_ok(mesh: &TriMesh, options: &PerceptionOptions) -> Perception {
        let rgba = vec![[180, 180, 180, 255]; mesh.triangle_count()];
        match perceive(mesh, &rgba, &[], &BuiltinSegmenter::default(), options) {
            Ok(p) => p,
            Err(e) => panic!("perceive: {e}"),
        }
    }

    #[test]
    fn a_box_with_a_lid_gives_two_merged_masks_and_a_prior_of_two() {
        let mesh = box_with_inset_lid();
        let p = perceive_ok(&mesh, &small_views());
        assert_eq!(p.provider, "builtin-render-segmenter");
        assert_eq!(p.per_view.len(), 8);
        assert_eq!(p.merged.len(), 2, "{:?}", p.merged);
        let body = CUBOID_FACES as u32;
        // Largest first: the box, then the lid, each made only of its own faces.
        assert!(p.merged[0].iter().all(|&f| f < body), "{:?}", p.merged);
        assert!(p.merged[1].iter().all(|&f| f >= body), "{:?}", p.merged);
        // The lid's top (faces 14, 15) and its four sides are seen; its bottom (12, 13) never.
        assert_eq!(p.merged[1], (14..24).collect::<Vec<u32>>());
        assert!(!p.visible_faces[12] && !p.visible_faces[13]);
        assert!(p.visible_faces[..12].iter().all(|&v| v));
        assert_eq!(p.k_prior, 2);
    }

    #[test]
    fn a_single_box_gives_one_mask_and_a_prior_of_one() {
        let mesh = TriMesh::cuboid(DVec3::ZERO, DVec3::new(0.5, 0.3, 0.2));
        let p = perceive_ok(&mesh, &small_views());
        assert_eq!(p.merged, vec![(0..12).collect::<Vec<u32>>()]);
        assert_eq!(p.k_prior, 1);
        assert!(p.per_view.iter().all(|masks| masks.len() == 1));
    }

    #[test]
    fn the_result_does_not_depend_on_threads_or_runs() {
        let mesh = box_with_inset_lid();
        let one = perceive_ok(&mesh, &small_views());
        let again = perceive_ok(&mesh, &small_views());
        let threaded = perceive_ok(
            &mesh,
            &PerceptionOptions {
                threads: 3,
                ..small_views()
            },
        );
        for other in [&again, &threaded] {
            assert_eq!(one.per_view, other.per_view);
            assert_eq!(one.merged, other.merged);
            assert_eq!(one.k_prior, other.k_prior);
            assert_eq!(one.views.face_ids[5].face, other.views.face_ids[5].face);
        }
    }

    /// Labels every pixel `label`, or returns a map of the wrong size.
    struct Fixed {
        label: i32,
        wrong_size: bool,
    }

    impl Segmenter for Fixed {
        fn provider(&self) -> String {
            "fixed".into()
        }

        fn segment(&self, view: &ViewImage<'_>) -> DecomposeResult<LabelMap> {
            let (w, h) = (view.face_ids.width_px, view.face_ids.height_px);
            let mut map = LabelMap::unlabelled(w + u32::from(self.wrong_size), h);
            map.labels.fill(self.label);
            Ok(map)
        }
    }

    #[test]
    fn unusable_segmentations_and_inputs_are_errors() {
        let mesh = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let rgba = vec![[255; 4]; 12];
        let options = PerceptionOptions {
            threads: 2,
            ..small_views()
        };
        let run = |segmenter: &dyn Segmenter, materials: &[u32]| {
            perceive(&mesh, &rgba, materials, segmenter, &options).map(|p| p.merged)
        };
        let wrong = Fixed {
            label: 0,
            wrong_size: true,
        };
        assert!(matches!(
            run(&wrong, &[]),
            Err(DecomposeError::Segmentation { view: 0, .. })
        ));
        let empty = Fixed {
            label: -1,
            wrong_size: false,
        };
        assert!(matches!(run(&empty, &[]), Err(DecomposeError::NoMasks)));
        let whole = Fixed {
            label: 0,
            wrong_size: false,
        };
        assert!(matches!(run(&whole, &[0; 12]), Ok(m) if m.len() == 1));
        assert!(matches!(
            run(&whole, &[0; 5]),
            Err(DecomposeError::InvalidInput(_))
        ));
    }
}
