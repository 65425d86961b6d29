//! Pairing a prediction's parts with the ground truth's by where their surfaces lie, for
//! predictions whose part names say nothing of the truth (a decomposed mesh's `part_0`,
//! `part_1`, ...).
//!
//! Both sides' surfaces are sampled in their own `[0, 2]` model frames (so a run's unit and rest
//! translation cancel, as they do for pivots); each sample lies on the part of the other side
//! nearest to it, and on any other as near (surfaces that coincide at rest, such as a door's face
//! and the cabinet's front); the parts are matched one to one by the IoU of the surface they
//! share, as the optimal assignment over all pairs, and a pair sharing less than
//! [`MIN_MATCH_IOU`] is no match (the true part was not recovered, so its joint has no
//! prediction).

use std::collections::BTreeMap;

use serde::Serialize;
use uniphys_geometry::{DVec3, KdTree, TriMesh, min_cost_assignment, sample_points};

use crate::annotated::AnnotatedAsset;
use crate::{AnnotatedJoint, AnnotatedPart, EvalError, EvalResult};

/// A predicted part matched to a true part shares at least this IoU of surface with it (the
/// decomposition benchmark's bar for a recovered part).
pub const MIN_MATCH_IOU: f64 = 0.5;
/// Samples over each side's whole surface.
const SAMPLES_PER_SIDE: usize = 20_000;
/// A sample farther from every part of the other side than this many sample spacings (the side
/// of the square each sample stands for) lies on none of them.
const NEAR_SPACINGS: f64 = 3.0;

/// A part's surface, by part name, in its side's object frame and unit.
pub type PartSurface = (String, TriMesh);

/// One true part and the predicted part matched to it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartOverlap {
    /// The true part's name.
    pub gt_part: String,
    /// The matched predicted part's name (before renaming); `None` when no predicted part
    /// shares at least [`MIN_MATCH_IOU`] of surface with it.
    pub pred_part: Option<String>,
    /// IoU of the surface the two share (0 without a match).
    pub iou: f64,
}

/// Matches every true part to at most one predicted part by shared surface (see the module
/// documentation).
///
/// # Errors
/// [`EvalError::Mismatch`] when a side has no bounds or no part with a surface.
pub fn match_parts_by_overlap(
    pred: &AnnotatedAsset,
    pred_surfaces: &[PartSurface],
    gt: &AnnotatedAsset,
    gt_surfaces: &[PartSurface],
) -> EvalResult<Vec<PartOverlap>> {
    let pred_side = Side::new(pred, pred_surfaces, "prediction")?;
    let gt_side = Side::new(gt, gt_surfaces, "ground truth")?;
    let (t, k) = (gt_side.parts.len(), pred_side.parts.len());
    // Shared area seen from each side, averaged.
    let from_gt = gt_side.area_on(&pred_side);
    let from_pred = pred_side.area_on(&gt_side);
    let shared = |g: usize, p: usize| 0.5 * (from_gt[g * k + p] + from_pred[p * t + g]);
    let iou = |g: usize, p: usize| {
        let x = shared(g, p);
        let union = gt_side.parts[g].area + pred_side.parts[p].area - x;
        if union > 0.0 { x / union } else { 0.0 }
    };
    let cost: Vec<f64> = (0..t * k).map(|c| 1.0 - iou(c / k, c % k)).collect();
    let assignment = min_cost_assignment(&cost, t, k)
        .map_err(|e| EvalError::Mismatch(format!("part matching failed: {e}")))?;
    Ok(gt_side
        .parts
        .iter()
        .zip(assignment)
        .enumerate()
        .map(|(g, (part, p))| {
            let matched = p
                .map(|p| (p, iou(g, p)))
                .filter(|&(_, x)| x >= MIN_MATCH_IOU);
            PartOverlap {
                gt_part: part.name.clone(),
                pred_part: matched.map(|(p, _)| pred_side.parts[p].name.clone()),
                iou: matched.map_or(0.0, |(_, x)| x),
            }
        })
        .collect())
}

/// The prediction with each matched part renamed to its true part's name, and every other part
/// to `unmatched <name>` (so no name is paired by accident); joints and their groups follow.
#[must_use]
pub fn renamed_by_overlap(pred: &AnnotatedAsset, matches: &[PartOverlap]) -> AnnotatedAsset {
    let to_true: BTreeMap<&str, &str> = matches
        .iter()
        .filter_map(|m| Some((m.pred_part.as_deref()?, m.gt_part.as_str())))
        .collect();
    let rename = |name: &str| {
        to_true
            .get(name)
            .map_or_else(|| format!("unmatched {name}"), |&t| t.to_owned())
    };
    let mut out = pred.clone();
    out.parts = pred
        .parts
        .iter()
        .map(|p| AnnotatedPart {
            name: rename(&p.name),
            physics: p.physics.clone(),
        })
        .collect();
    out.joints = pred
        .joints
        .iter()
        .map(|j| {
            let mut members: Vec<String> = j.members.iter().map(|m| rename(m)).collect();
            members.sort();
            AnnotatedJoint {
                child: rename(&j.child),
                members,
                ..j.clone()
            }
        })
        .collect();
    out
}

/// One part's samples in the model frame.
struct SampledPart {
    name: String,
    /// Surface area in model units squared.
    area: f64,
    points: Vec<DVec3>,
    tree: KdTree,
}

/// One side's parts, sampled.
struct Side {
    parts: Vec<SampledPart>,
    /// Side of the square of surface one sample stands for, model units.
    spacing: f64,
}

impl Side {
    fn new(asset: &AnnotatedAsset, surfaces: &[PartSurface], what: &str) -> EvalResult<Self> {
        let frame = asset.model_frame().ok_or_else(|| {
            EvalError::Mismatch(format!(
                "{what} {}: no bounds, so its parts cannot be placed for matching by overlap",
                asset.origin
            ))
        })?;
        let in_model: Vec<(String, TriMesh)> = surfaces
            .iter()
            .map(|(name, mesh)| {
                let positions = mesh
                    .positions
                    .iter()
                    .map(|&p| frame.point_source_to_model(p))
                    .collect();
                let mesh = TriMesh {
                    positions,
                    triangles: mesh.triangles.clone(),
                    ..TriMesh::default()
                };
                (name.clone(), mesh)
            })
            .collect();
        let total: f64 = in_model.iter().map(|(_, m)| m.area()).sum();
        if total.is_nan() || total <= 0.0 {
            return Err(EvalError::Mismatch(format!(
                "{what} {}: no part has a surface to match by overlap",
                asset.origin
            )));
        }
        let parts = in_model
            .into_iter()
            .enumerate()
            .map(|(i, (name, mesh))| {
                let area = mesh.area();
                let count = ((SAMPLES_PER_SIDE as f64 * area / total).round() as usize)
                    .max(usize::from(area > 0.0));
                let points = sample_points(&mesh, count, 17 + i as u64);
                SampledPart {
                    name,
                    area,
                    tree: KdTree::new(points.clone()),
                    points,
                }
            })
            .collect();
        Ok(Self {
            parts,
            spacing: (total / SAMPLES_PER_SIDE as f64).sqrt(),
        })
    }

    /// Row-major `self parts x other parts`: the area of each part of this side whose samples
    /// lie on each part of `other`: on the nearest one if it is near enough, and on every other
    /// one about as near (within a sample spacing: a door's face that coincides with the
    /// cabinet's front at rest lies on both).
    fn area_on(&self, other: &Self) -> Vec<f64> {
        let k = other.parts.len();
        let spacing = self.spacing.max(other.spacing);
        let mut area = vec![0.0; self.parts.len() * k];
        let mut distances = vec![0.0; k];
        for (i, part) in self.parts.iter().enumerate() {
            let weight = part.area / part.points.len().max(1) as f64;
            for &q in &part.points {
                for (d, o) in distances.iter_mut().zip(&other.parts) {
                    *d = o.tree.nearest_distance(q);
                }
                let nearest = distances.iter().copied().fold(f64::INFINITY, f64::min);
                if nearest > NEAR_SPACINGS * spacing {
                    continue;
                }
                for (j, &d) in distances.iter().enumerate() {
                    if d <= nearest + spacing {
                        area[i * k + j] += weight;
                    }
                }
            }
        }
        area
    }
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::{DMat4, DVec3, TriMesh};

    use super::*;
    use crate::annotated::union_bounds;

    fn body() -> TriMesh {
        TriMesh::cuboid(DVec3::ZERO, DVec3::ONE)
    }

    fn door() -> TriMesh {
        TriMesh::cuboid(DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.05, 1.0, 1.0))
    }

    fn side(surfaces: &[PartSurface], joint_child: &str) -> AnnotatedAsset {
        let bounds = surfaces.iter().fold(None, |acc, (_, m)| {
            let b = m.bounds();
            union_bounds(acc, b.min.to_array(), b.max.to_array())
        });
        AnnotatedAsset {
            origin: "test".to_owned(),
            bounds_in_object: bounds,
            parts: surfaces
                .iter()
                .map(|(name, _)| AnnotatedPart {
                    name: name.clone(),
                    physics: None,
                })
                .collect(),
            joints: vec![AnnotatedJoint {
                child: joint_child.to_owned(),
                motion_type: 'C',
                axis: [0.0, 0.0, 1.0],
                pivot_in_object: Some([1.0, 0.0, 0.0]),
                range: Some([0.0, 1.57]),
                members: vec![joint_child.to_owned()],
            }],
            object: None,
        }
    }

    #[test]
    fn parts_in_another_order_unit_and_place_are_matched_by_the_surface_they_share() {
        let gt_surfaces = vec![("body".to_owned(), body()), ("door".to_owned(), door())];
        let gt = side(&gt_surfaces, "door");
        // The prediction in centimetres, shifted, its parts in the other order and unnamed.
        let to_pred = DMat4::from_translation(DVec3::new(3.0, -2.0, 0.5))
            * DMat4::from_scale(DVec3::splat(100.0));
        let pred_surfaces = vec![
            ("part_0".to_owned(), door().transformed(&to_pred)),
            ("part_1".to_owned(), body().transformed(&to_pred)),
        ];
        let pred = side(&pred_surfaces, "part_0");
        let matches =
            match_parts_by_overlap(&pred, &pred_surfaces, &gt, &gt_surfaces).expect("matched");
        let of = |name: &str| {
            matches
                .iter()
                .find(|m| m.gt_part == name)
                .expect("every true part is listed")
        };
        assert_eq!(of("door").pred_part.as_deref(), Some("part_0"));
        assert_eq!(of("body").pred_part.as_deref(), Some("part_1"));
        assert!(of("door").iou > 0.9 && of("body").iou > 0.9, "{matches:?}");
        let renamed = renamed_by_overlap(&pred, &matches);
        assert_eq!(renamed.joints[0].child, "door");
        assert_eq!(renamed.joints[0].members, vec!["door".to_owned()]);
        assert_eq!(renamed.parts[1].name, "body");
    }

    #[test]
    fn a_true_part_swallowed_by_a_bigger_one_has_no_match_and_nothing_takes_its_name() {
        let gt_surfaces = vec![("body".to_owned(), body()), ("door".to_owned(), door())];
        let gt = side(&gt_surfaces, "door");
        let whole = TriMesh::merge([&body(), &door()]);
        let pred_surfaces = vec![("part_0".to_owned(), whole)];
        let pred = side(&pred_surfaces, "part_0");
        let matches =
            match_parts_by_overlap(&pred, &pred_surfaces, &gt, &gt_surfaces).expect("matched");
        let door_match = matches.iter().find(|m| m.gt_part == "door").expect("door");
        assert_eq!(door_match.pred_part, None, "{matches:?}");
        assert_eq!(door_match.iou, 0.0);
        // The body is most of the whole, so the one part is the body: its joint is not the door's.
        let renamed = renamed_by_overlap(&pred, &matches);
        assert_eq!(renamed.parts[0].name, "body");
        assert!(renamed.joint_of("door").is_none());
    }

    #[test]
    fn a_part_that_shares_less_than_half_is_renamed_as_unmatched() {
        let gt_surfaces = vec![("door".to_owned(), door())];
        let gt = side(&gt_surfaces, "door");
        // A third of the door's height: its surface is well under half the union.
        let sliver = TriMesh::cuboid(DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.05, 1.0, 0.3));
        let pred_surfaces = vec![("part_7".to_owned(), sliver)];
        let pred = side(&pred_surfaces, "part_7");
        let matches =
            match_parts_by_overlap(&pred, &pred_surfaces, &gt, &gt_surfaces).expect("matched");
        assert_eq!(matches[0].pred_part, None, "{matches:?}");
        let renamed = renamed_by_overlap(&pred, &matches);
        assert_eq!(renamed.parts[0].name, "unmatched part_7");
        assert_eq!(renamed.joints[0].child, "unmatched part_7");
    }

    #[test]
    fn a_side_without_bounds_or_surfaces_is_refused_with_the_reason() {
        let gt_surfaces = vec![("door".to_owned(), door())];
        let gt = side(&gt_surfaces, "door");
        let mut pred = side(&gt_surfaces, "door");
        pred.bounds_in_object = None;
        let error =
            match_parts_by_overlap(&pred, &gt_surfaces, &gt, &gt_surfaces).expect_err("no bounds");
        assert!(error.to_string().contains("no bounds"), "{error}");
        let error = match_parts_by_overlap(&gt, &[], &gt, &gt_surfaces).expect_err("no surface");
        assert!(
            error.to_string().contains("no part has a surface"),
            "{error}"
        );
    }
}
