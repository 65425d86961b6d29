use uniphys_geometry::{Aabb, DVec3};

use super::colours::{INK, PIVOT_COLOURS};
use super::layers::{SplitScene, TargetStyle, context_image};
use super::panel::{font_scale, legend, titled_panel};
use super::{PartScene, VIEW_DIRECTIONS, ViewOptions};
use crate::draw;
use crate::rgba::RgbaImage;
use crate::rig::camera_from_direction;

/// Opacity of the part in the pivot views.
const PART_ALPHA: f64 = 0.5;

/// Pivot-candidate views from two viewpoints ([`VIEW_DIRECTIONS`]): the part translucent in its
/// colour (the rest faint grey), the 6 pivots as coloured discs with a dark outline drawn on top
/// in candidate order ([`PIVOT_COLOURS`]), a legend; one titled panel per view. Non-finite pivots
/// are not drawn. The camera frames the part and all pivots.
#[must_use]
pub fn pivot_candidate_views(
    scene: &PartScene<'_>,
    part: usize,
    pivots: &[DVec3; 6],
    options: &ViewOptions,
) -> [RgbaImage; 2] {
    let size = options.panel_px.max(16);
    let scale = font_scale(size);
    let split = SplitScene::new(scene, part);
    let framed = pivots
        .iter()
        .filter(|p| p.is_finite())
        .fold(split.target_bounds(), |b: Aabb, &p| b.grown(p));
    let entries: Vec<(String, [u8; 4])> = PIVOT_COLOURS
        .iter()
        .map(|(name, rgba)| ((*name).to_owned(), *rgba))
        .collect();
    let legend = legend(&entries, size, scale);
    let radius_px = (f64::from(size) / 48.0).max(4.0);
    VIEW_DIRECTIONS.map(|dir| {
        let view = usize::from(dir[1] > 0.0);
        let camera = camera_from_direction(&framed, DVec3::from_array(dir), size, size);
        let mut body = context_image(&split, &camera, TargetStyle::Translucent(PART_ALPHA));
        for (pivot, (_, rgba)) in pivots.iter().zip(PIVOT_COLOURS) {
            if !pivot.is_finite() {
                continue;
            }
            let Some(p) = camera.project(*pivot) else {
                continue;
            };
            draw::disc(&mut body, [p.x_px, p.y_px], radius_px + 1.5, INK);
            draw::disc(&mut body, [p.x_px, p.y_px], radius_px, rgba);
        }
        titled_panel(
            &format!("Candidate pivot points (camera view {view})"),
            &body,
            Some(&legend),
            scale,
        )
    })
}
