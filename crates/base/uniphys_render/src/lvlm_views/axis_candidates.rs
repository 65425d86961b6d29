use uniphys_geometry::{Aabb, DVec3};

use super::colours::{AXIS_COLOURS, FRAME_AXIS_NAMES, INK, WHITE};
use super::layers::{SplitScene, TargetStyle, context_image};
use super::panel::{font_scale, legend, titled_panel};
use super::{PANEL_GAP_PX, PartScene, VIEW_DIRECTIONS, ViewOptions};
use crate::camera::Camera;
use crate::draw;
use crate::rgba::{RgbaImage, hstack};
use crate::rig::camera_from_direction;

/// Arrow length as a multiple of the part's bounding-box diagonal (the reference's 1.6).
pub const ARROW_LENGTH_PER_DIAGONAL: f64 = 1.6;

/// Candidate-axis views from two viewpoints ([`VIEW_DIRECTIONS`]): for each, a two-panel image:
/// left the 7 contact candidates `axes[0..7]` as coloured arrows through `origin_m` (length 1.6 x
/// the part's bounding-box diagonal, centred on the origin, head at the positive end), right the
/// 3 frame axes `axes[7..10]` labelled X, Y, Z; the part in its colour, the rest translucent
/// grey; under each panel a legend with each colour's name ([`AXIS_COLOURS`]). Axes need not be
/// unit; zero or non-finite axes are not drawn. The camera frames the part and all arrows.
#[must_use]
pub fn axis_candidate_views(
    scene: &PartScene<'_>,
    part: usize,
    axes: &[DVec3; 10],
    origin_m: DVec3,
    options: &ViewOptions,
) -> [RgbaImage; 2] {
    let size = options.panel_px.max(16);
    let scale = font_scale(size);
    let split = SplitScene::new(scene, part);
    let part_bounds = split.target_bounds();
    let length_m = ARROW_LENGTH_PER_DIAGONAL * part_bounds.diagonal().max(1e-3);
    let arrows: Vec<Option<(DVec3, DVec3)>> = axes
        .iter()
        .map(|a| {
            let u = a.normalize_or_zero();
            (u != DVec3::ZERO && origin_m.is_finite())
                .then(|| (origin_m - 0.5 * length_m * u, origin_m + 0.5 * length_m * u))
        })
        .collect();
    let framed = arrows
        .iter()
        .flatten()
        .fold(part_bounds, |b: Aabb, &(from, to)| b.grown(from).grown(to));

    let contact_legend: Vec<(String, [u8; 4])> = AXIS_COLOURS[..7]
        .iter()
        .map(|(name, rgba)| ((*name).to_owned(), *rgba))
        .collect();
    let frame_legend: Vec<(String, [u8; 4])> = AXIS_COLOURS[7..]
        .iter()
        .zip(FRAME_AXIS_NAMES)
        .map(|((name, rgba), axis)| (format!("{name} = {axis} axis"), *rgba))
        .collect();
    let contact_legend = legend(&contact_legend, size, scale);
    let frame_legend = legend(&frame_legend, size, scale);

    VIEW_DIRECTIONS.map(|dir| {
        let view = usize::from(dir[1] > 0.0);
        let camera = camera_from_direction(&framed, DVec3::from_array(dir), size, size);
        let base = context_image(&split, &camera, TargetStyle::Opaque);
        let mut left = base.clone();
        let mut right = base;
        for (i, arrow) in arrows.iter().enumerate() {
            let Some((from, to)) = arrow else { continue };
            let (img, label) = if i < 7 {
                (&mut left, None)
            } else {
                (&mut right, FRAME_AXIS_NAMES.get(i - 7).copied())
            };
            draw_axis_arrow(img, &camera, *from, *to, AXIS_COLOURS[i].1, label, scale);
        }
        for img in [&mut left, &mut right] {
            if let Some(o) = camera.project(origin_m) {
                draw::disc(img, [o.x_px, o.y_px], 1.5 * f64::from(scale) + 1.0, INK);
            }
        }
        let left = titled_panel(
            &format!("Candidate axes (camera view {view})"),
            &left,
            Some(&contact_legend),
            scale,
        );
        let right = titled_panel(
            &format!("XYZ axes (camera view {view})"),
            &right,
            Some(&frame_legend),
            scale,
        );
        hstack(&[left, right], PANEL_GAP_PX, WHITE)
    })
}

/// One arrow from `from` to `to` (world), with an optional label past its tip.
fn draw_axis_arrow(
    img: &mut RgbaImage,
    camera: &Camera,
    from: DVec3,
    to: DVec3,
    rgba: [u8; 4],
    label: Option<&str>,
    scale: u32,
) {
    let (Some(a), Some(b)) = (camera.project(from), camera.project(to)) else {
        return;
    };
    let thickness = (f64::from(img.width_px) / 110.0).max(2.0);
    let head = 4.5 * thickness;
    draw::arrow(
        img,
        [a.x_px, a.y_px],
        [b.x_px, b.y_px],
        thickness,
        head,
        rgba,
    );
    if let Some(label) = label {
        let (dx, dy) = (b.x_px - a.x_px, b.y_px - a.y_px);
        let len = (dx * dx + dy * dy).sqrt().max(1e-9);
        let (w, h) = draw::text_size(label, scale);
        let offset = 0.5 * head + f64::from(w.max(h));
        let cx = b.x_px + dx / len * offset - 0.5 * f64::from(w);
        let cy = b.y_px + dy / len * offset - 0.5 * f64::from(h);
        draw::text(img, cx.round() as i32, cy.round() as i32, label, scale, INK);
    }
}
