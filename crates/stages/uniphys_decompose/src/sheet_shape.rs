//! A part's flat shape, for the steps that look for sheets ([`crate::layers`], [`crate::tops`]):
//! its principal frame from samples of its surface, and its extents along that frame over its
//! faces' corners.

use uniphys_geometry::{DVec3, TriMesh, extent_along, principal_axes, sample_points};

/// A part's principal frame and extents.
pub(crate) struct SheetShape {
    /// Samples of its surface.
    pub(crate) samples: Vec<DVec3>,
    /// Its principal axes, widest spread first: a sheet's normal last.
    pub(crate) axes: [DVec3; 3],
    /// Its faces' corners.
    pub(crate) corners: Vec<DVec3>,
    /// Its extents along the axes (length, width, thickness), metres.
    pub(crate) extents_m: [f64; 3],
}

impl SheetShape {
    /// The shape of the part meshed as `part`, whose faces' corners are `corners`, from
    /// `samples` samples drawn with `seed`; `None` with fewer than 3 samples.
    pub(crate) fn of(
        part: &TriMesh,
        corners: Vec<DVec3>,
        samples: usize,
        seed: u64,
    ) -> Option<Self> {
        let samples = sample_points(part, samples, seed);
        if samples.len() < 3 {
            return None;
        }
        let axes = principal_axes(&samples);
        let extents_m = axes.map(|a| extent_along(&corners, a));
        Some(Self {
            samples,
            axes,
            corners,
            extents_m,
        })
    }

    /// Whether it is a broad thin sheet: its thickness at most `thin_ratio_max` of its length,
    /// its width at least `broad_ratio_min` of it.
    pub(crate) fn is_broad_sheet(&self, thin_ratio_max: f64, broad_ratio_min: f64) -> bool {
        let [length, width, thickness] = self.extents_m;
        length > 0.0 && thickness <= thin_ratio_max * length && width >= broad_ratio_min * length
    }
}
