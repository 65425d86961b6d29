//! A part's box along its own box axes, from its surface samples.

use std::cell::OnceCell;
use std::sync::Arc;

use uniphys_geometry::{DVec3, OrientedBox, box_axes, projection_range};

use crate::scene::Scene;

/// Samples with their box, found at most once however many rules of a sweep ask for it (a box
/// search is a convex hull and a rotating search); with [`Boxed::of_parts`], at most once per
/// scene for those parts however many sweeps ask (a correction sweeps dozens of variants of one
/// part).
pub(crate) struct Boxed<'a> {
    pub(crate) points: &'a [DVec3],
    part_box: OnceCell<Arc<PartBox>>,
    /// The scene and the parts `points` sample, whose box the scene keeps.
    parts: Option<(&'a Scene, &'a [usize])>,
}

impl<'a> Boxed<'a> {
    pub(crate) fn new(points: &'a [DVec3]) -> Self {
        Self {
            points,
            part_box: OnceCell::new(),
            parts: None,
        }
    }

    /// The samples `points` of `scene`'s `parts` (as [`Scene::points_of`] gives them).
    pub(crate) fn of_parts(points: &'a [DVec3], scene: &'a Scene, parts: &'a [usize]) -> Self {
        Self {
            parts: Some((scene, parts)),
            ..Self::new(points)
        }
    }

    /// [`PartBox::of`] the samples.
    pub(crate) fn part_box(&self) -> &PartBox {
        self.part_box.get_or_init(|| match self.parts {
            Some((scene, parts)) => scene.part_box(parts, self.points),
            None => Arc::new(PartBox::of(self.points)),
        })
    }
}

/// A part's box: axes, projection ranges, centre and diagonal (object frame, metres).
#[derive(Debug, Clone, PartialEq)]
pub struct PartBox {
    /// The part's box axes (unit, orthogonal).
    pub axes: [DVec3; 3],
    /// The samples' projection range along each axis.
    pub ranges: [(f64, f64); 3],
    /// The box's centre.
    pub centre: DVec3,
    /// The box's diagonal.
    pub diagonal: f64,
}

impl PartBox {
    /// The box of `points` along their box axes.
    #[must_use]
    pub fn of(points: &[DVec3]) -> Self {
        let axes = box_axes(points);
        let ranges = axes.map(|a| projection_range(points, a));
        let centre = (0..3)
            .map(|k| axes[k] * (0.5 * (ranges[k].0 + ranges[k].1)))
            .sum();
        let diagonal = ranges
            .iter()
            .map(|(lo, hi)| (hi - lo).powi(2))
            .sum::<f64>()
            .sqrt();
        Self {
            axes,
            ranges,
            centre,
            diagonal,
        }
    }

    /// The same box as its centre, axes and half extents (what [`uniphys_geometry::carve_out`]
    /// carves hulls around).
    #[must_use]
    pub fn oriented(&self) -> OrientedBox {
        OrientedBox {
            centre: self.centre,
            axes: self.axes,
            half_extents: DVec3::new(self.extent(0), self.extent(1), self.extent(2)) * 0.5,
        }
    }

    /// The extent along axis `k`.
    #[must_use]
    pub fn extent(&self, k: usize) -> f64 {
        (self.ranges[k].1 - self.ranges[k].0).max(0.0)
    }

    /// Whether `point` lies in the box (on its faces included).
    #[must_use]
    pub fn contains(&self, point: DVec3) -> bool {
        (0..3).all(|k| {
            let x = point.dot(self.axes[k]);
            x >= self.ranges[k].0 && x <= self.ranges[k].1
        })
    }

    /// The index of the thinnest axis (the first of equally thin ones).
    #[must_use]
    pub fn thinnest_axis(&self) -> usize {
        (0..3)
            .min_by(|&a, &b| self.extent(a).total_cmp(&self.extent(b)))
            .unwrap_or(0)
    }

    /// Extents sorted from thinnest to thickest.
    #[must_use]
    pub fn sorted_extents(&self) -> [f64; 3] {
        let mut e = [self.extent(0), self.extent(1), self.extent(2)];
        e.sort_by(f64::total_cmp);
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_oriented_box_of_a_turned_slab_has_its_edges() {
        let r = uniphys_geometry::DMat3::from_rotation_z(0.5);
        let points: Vec<DVec3> =
            uniphys_geometry::TriMesh::cuboid(DVec3::splat(-0.5), DVec3::new(0.5, 0.2, 0.1))
                .positions
                .iter()
                .map(|p| r * *p)
                .collect();
        let b = PartBox::of(&points).oriented();
        let mut half = b.half_extents.to_array();
        half.sort_by(f64::total_cmp);
        assert!(
            (half[0] - 0.3).abs() < 1e-6 && (half[2] - 0.5).abs() < 1e-6,
            "{half:?}"
        );
    }

    #[test]
    fn a_scene_finds_the_box_of_a_set_of_parts_once_for_every_sweep() {
        use uniphys_geometry::TriMesh;
        let slab = TriMesh::cuboid(DVec3::ZERO, DVec3::new(0.5, 0.2, 0.1));
        let block = TriMesh::cuboid(DVec3::new(0.6, 0.0, 0.0), DVec3::new(0.9, 0.3, 0.3));
        let scene = Scene::of_convex_parts(&[slab, block], 500);
        let both = [0, 1];
        let points = scene.points_of(&both);
        let first = Boxed::of_parts(&points, &scene, &both);
        let again = Boxed::of_parts(&points, &scene, &both);
        assert!(
            std::ptr::eq(first.part_box(), again.part_box()),
            "found once"
        );
        assert_eq!(*first.part_box(), PartBox::of(&points), "the same box");
        let slab_points = scene.points_of(&[0]);
        let slab_box = Boxed::of_parts(&slab_points, &scene, &[0]);
        assert_eq!(
            *slab_box.part_box(),
            PartBox::of(&slab_points),
            "kept per set of parts"
        );
    }
}
