//! `renders/preview.png`: the asset at rest from four viewpoints around and above it, each part in
//! its own colour (the dashboard's 3D view uses the same colours), Lambert-shaded, on a light
//! background. For people browsing results; nothing reads it back.

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_render::{
    RgbaImage, camera_from_direction, encode_png, hstack, render_face_ids, shade,
};

use crate::PipelineResult;

/// Where the preview goes among the exported files.
pub(crate) const PREVIEW_PATH: &str = "renders/preview.png";
/// Width and height of each view, pixels.
const VIEW_PX: u32 = 320;
/// Gap between views, pixels.
const GAP_PX: u32 = 4;
/// Background (the dashboard's viewer background).
const BACKGROUND: [u8; 4] = [243, 245, 248, 255];
/// Degrees between consecutive part hues: a golden angle, so hues never repeat.
const GOLDEN_ANGLE_DEG: f64 = 137.508;

/// The PNG of the parts `meshes` (object frame, Z up).
pub(crate) fn preview_png(meshes: &[TriMesh]) -> PipelineResult<Vec<u8>> {
    let merged = TriMesh::merge(meshes);
    let mut part_of_face = Vec::with_capacity(merged.triangles.len());
    for (part, mesh) in meshes.iter().enumerate() {
        part_of_face.extend(std::iter::repeat_n(part, mesh.triangles.len()));
    }
    let colours: Vec<[u8; 4]> = (0..meshes.len()).map(part_colour).collect();
    let bounds = merged.bounds();
    let views: Vec<RgbaImage> = [(1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .into_iter()
        .map(|(x, y)| {
            let direction = DVec3::new(x, y, 0.8).normalize();
            let camera = camera_from_direction(&bounds, direction, VIEW_PX, VIEW_PX);
            let ids = render_face_ids(&merged, &camera);
            let mut image = shade(&ids, &camera, &|face| {
                part_of_face
                    .get(face)
                    .map_or([128, 128, 128, 255], |&p| colours[p])
            });
            for pixel in &mut image.pixels {
                if pixel[3] == 0 {
                    *pixel = BACKGROUND;
                }
            }
            image
        })
        .collect();
    Ok(encode_png(&hstack(&views, GAP_PX, [255; 4]))?)
}

/// The `n`-th part's colour: HSL with hue `n` golden angles from 210°, saturation 0.62,
/// lightness 0.52 (as the dashboard's `palette.js`).
fn part_colour(n: usize) -> [u8; 4] {
    #[expect(clippy::cast_precision_loss, reason = "part indices are small")]
    let hue_deg = (n as f64 * GOLDEN_ANGLE_DEG + 210.0) % 360.0;
    let [r, g, b] = hsl_to_rgb(hue_deg / 360.0, 0.62, 0.52);
    [r, g, b, 255]
}

/// sRGB bytes of an HSL colour (components in [0, 1]).
fn hsl_to_rgb(h: f64, s: f64, l: f64) -> [u8; 3] {
    let q = if l < 0.5 {
        l * (1.0 + s)
    } else {
        l + s - l * s
    };
    let p = 2.0 * l - q;
    let channel = |t: f64| {
        let t = t.rem_euclid(1.0);
        let v = if t < 1.0 / 6.0 {
            p + (q - p) * 6.0 * t
        } else if t < 0.5 {
            q
        } else if t < 2.0 / 3.0 {
            p + (q - p) * (2.0 / 3.0 - t) * 6.0
        } else {
            p
        };
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to 0..=255"
        )]
        let byte = (v * 255.0).round().clamp(0.0, 255.0) as u8;
        byte
    };
    [channel(h + 1.0 / 3.0), channel(h), channel(h - 1.0 / 3.0)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hsl_matches_known_colours() {
        assert_eq!(hsl_to_rgb(0.0, 1.0, 0.5), [255, 0, 0]);
        assert_eq!(hsl_to_rgb(1.0 / 3.0, 1.0, 0.5), [0, 255, 0]);
        assert_eq!(hsl_to_rgb(2.0 / 3.0, 1.0, 0.5), [0, 0, 255]);
        assert_eq!(hsl_to_rgb(0.5, 0.0, 0.5), [128, 128, 128]);
    }

    #[test]
    fn neighbouring_parts_get_distinct_colours() {
        let colours: Vec<[u8; 4]> = (0..12).map(part_colour).collect();
        for (i, a) in colours.iter().enumerate() {
            for b in &colours[i + 1..] {
                let distance: i32 = a
                    .iter()
                    .zip(b)
                    .map(|(x, y)| (i32::from(*x) - i32::from(*y)).abs())
                    .sum();
                assert!(distance > 30, "{a:?} and {b:?} are too close");
            }
        }
    }

    #[test]
    fn the_preview_shows_every_part_of_two_boxes_in_four_views() {
        let boxes = [
            TriMesh::cuboid(DVec3::new(-0.3, -0.2, 0.0), DVec3::new(0.3, 0.2, 0.5)),
            TriMesh::cuboid(DVec3::new(-0.3, -0.2, 0.5), DVec3::new(0.3, 0.2, 0.55)),
        ];
        let png = preview_png(&boxes).expect("renders");
        let image = uniphys_render::decode_png(&png).expect("decodes");
        assert_eq!(image.width_px, 4 * VIEW_PX + 3 * GAP_PX);
        assert_eq!(image.height_px, VIEW_PX);
        for part in 0..2 {
            let [r, g, b, _] = part_colour(part);
            // Lambert shading scales a colour by a factor in [AMBIENT, 1]: compare hues by the
            // channels' order, which shading keeps.
            let shows = image.pixels.iter().any(|p| {
                let scale = f64::from(p[0].max(p[1]).max(p[2])) / f64::from(r.max(g).max(b));
                let close = |c: u8, want: u8| (f64::from(c) - scale * f64::from(want)).abs() < 6.0;
                p[3] == 255
                    && *p != BACKGROUND
                    && close(p[0], r)
                    && close(p[1], g)
                    && close(p[2], b)
            });
            assert!(shows, "part {part} is visible in its colour");
        }
    }
}
