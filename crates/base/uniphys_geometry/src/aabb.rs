use glam::DVec3;

/// Axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: DVec3,
    /// Maximum corner.
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf); growing it by any point gives that point.
    pub const EMPTY: Self = Self {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The smallest box containing all `points`; [`Aabb::EMPTY`] for no points.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a DVec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grown(*p))
    }

    /// This box grown to contain `p`.
    #[must_use]
    pub fn grown(self, p: DVec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box containing both boxes.
    #[must_use]
    pub fn union(self, other: Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether the box contains no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Side lengths (zero for an empty box).
    #[must_use]
    pub fn extents(&self) -> DVec3 {
        if self.is_empty() {
            DVec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Centre point.
    #[must_use]
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Length of the diagonal: the object scale that relative thresholds are based on.
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        self.extents().length()
    }

    /// Longest side length.
    #[must_use]
    pub fn max_extent(&self) -> f64 {
        self.extents().max_element()
    }
}
