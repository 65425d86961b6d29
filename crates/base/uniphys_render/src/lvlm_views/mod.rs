//! The images shown to the LVLM (reference §5 step 1 and §8), drawn by the CPU renderer:
//!
//! - [`part_composite`]: a part in the context of the whole object from two viewpoints, and alone;
//! - [`axis_candidate_views`]: the 10 candidate joint axes as coloured arrows ([`AXIS_COLOURS`]);
//! - [`pivot_candidate_views`]: the 6 candidate pivots as coloured discs ([`PIVOT_COLOURS`]).
//!
//! Every image is opaque on white, with titles and legends in the built-in font; the same input
//! always gives the same pixels.

mod axis_candidates;
mod colours;
mod layers;
mod panel;
mod part_composite;
mod pivot_candidates;

pub use axis_candidates::axis_candidate_views;
pub use colours::{AXIS_COLOURS, FRAME_AXIS_NAMES, PIVOT_COLOURS};
pub use part_composite::part_composite;
pub use pivot_candidates::pivot_candidate_views;

use uniphys_geometry::TriMesh;

/// The reference's two viewpoints (directions from the centre towards the eye, Z up): view 0
/// from the front right above, view 1 from the back right above.
pub const VIEW_DIRECTIONS: [[f64; 3]; 2] = [[0.5, -1.0, 0.5], [0.5, 1.0, 0.5]];

/// Pixels between panels placed side by side.
pub const PANEL_GAP_PX: u32 = 8;

/// The parts of an object in the world frame (metres) with their display colours.
#[derive(Debug, Clone, Copy)]
pub struct PartScene<'a> {
    /// One mesh per part.
    pub part_meshes: &'a [TriMesh],
    /// One RGBA colour per part (alpha ignored: parts are drawn opaque or with the view's own
    /// translucency); parts without a colour are drawn blue-grey.
    pub part_rgba: &'a [[u8; 4]],
}

/// Sizes of the LVLM views.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ViewOptions {
    /// Side of each square render panel in pixels (titles and legends come on top of it).
    pub panel_px: u32,
}

impl Default for ViewOptions {
    fn default() -> Self {
        Self { panel_px: 384 }
    }
}
