//! A part's box along its own box axes, from its surface samples.

use std::cell::OnceCell;

use uniphys_geometry::{DVec3, OrientedBox, box_axes, projection_range};

/// Samples with their box, found at most once however many rules of a sweep ask for it (a box
/// search is a convex hull and a rotating search).
pub(crate) struct Boxed<'a> {
    pub(crate) points: &'a [DVec3],
    part_box: OnceCell<PartBox>,
}

impl<'a> Boxed<'a> {
    pub(crate) fn new(points: &'a [DVec3]) -> Self {
        Self {
            points,
            part_box: OnceCell::new(),
        }
    }

    /// [`PartBox::of`] the samples.
    pub(crate) fn part_box(&self) -> &PartBox {
        self.part_box.get_or_init(|| PartBox::of(self.points))
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
}
