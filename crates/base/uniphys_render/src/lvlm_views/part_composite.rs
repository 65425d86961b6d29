use uniphys_geometry::DVec3;

use super::colours::WHITE;
use super::layers::{SplitScene, TargetStyle, alone_image, context_image};
use super::panel::{font_scale, titled_panel};
use super::{PANEL_GAP_PX, PartScene, VIEW_DIRECTIONS, ViewOptions};
use crate::rgba::{RgbaImage, hstack};
use crate::rig::camera_from_direction;

/// Context-preserving composite of part `part` (0-based; titles use label `part + 1`): three
/// titled, framed panels side by side: "part N (camera view 0)", "part N (camera view 1)": the
/// whole object, the target part in its colour and every other part light grey and translucent
/// (the target shows through parts in front of it), and "part N (alone)": the part by itself,
/// framed to fill the panel. Opaque, white background.
#[must_use]
pub fn part_composite(scene: &PartScene<'_>, part: usize, options: &ViewOptions) -> RgbaImage {
    let size = options.panel_px.max(16);
    let scale = font_scale(size);
    let split = SplitScene::new(scene, part);
    let label = part + 1;
    let object = split.object_bounds();
    let mut panels = Vec::with_capacity(3);
    for (view, dir) in VIEW_DIRECTIONS.iter().enumerate() {
        let camera = camera_from_direction(&object, DVec3::from_array(*dir), size, size);
        let body = context_image(&split, &camera, TargetStyle::Opaque);
        panels.push(titled_panel(
            &format!("part {label} (camera view {view})"),
            &body,
            None,
            scale,
        ));
    }
    let camera = camera_from_direction(
        &split.target_bounds(),
        DVec3::from_array(VIEW_DIRECTIONS[0]),
        size,
        size,
    );
    let body = alone_image(&split, &camera);
    panels.push(titled_panel(
        &format!("part {label} (alone)"),
        &body,
        None,
        scale,
    ));
    hstack(&panels, PANEL_GAP_PX, WHITE)
}
