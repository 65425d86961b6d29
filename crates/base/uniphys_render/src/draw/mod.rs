//! 2D drawing on [`RgbaImage`]s: anti-aliased lines, discs and arrows, rectangles and text in a
//! built-in 5x7 font. Coordinates are pixels, x right, y down; pixel `(i, j)` has its centre at
//! `(i + 0.5, j + 0.5)`, the convention of [`crate::Projected`]. Everything is composited
//! source-over and clipped to the image.

mod font;

pub use font::{ADVANCE, GLYPH_HEIGHT, GLYPH_WIDTH, LINE_ADVANCE, glyph};

use crate::rgba::RgbaImage;

/// Composites `rgba` at `(x, y)` with its alpha scaled by `coverage` in `[0, 1]`.
fn blend_covered(img: &mut RgbaImage, x: i64, y: i64, rgba: [u8; 4], coverage: f64) {
    if coverage <= 0.0 || x < 0 || y < 0 {
        return;
    }
    let (Ok(x), Ok(y)) = (u32::try_from(x), u32::try_from(y)) else {
        return;
    };
    let alpha = (f64::from(rgba[3]) * coverage.min(1.0)).round() as u8;
    img.blend(x, y, [rgba[0], rgba[1], rgba[2], alpha]);
}

/// Pixel index range whose centres can lie within `[lo, hi]`, clipped to `0..size`.
fn pixel_range(lo: f64, hi: f64, size: u32) -> std::ops::RangeInclusive<i64> {
    let a = (lo - 0.5).floor().max(0.0);
    let b = (hi - 0.5).ceil().min(f64::from(size) - 1.0);
    if a.is_nan() || b.is_nan() || a > b {
        #[allow(clippy::reversed_empty_ranges)]
        return 1..=0;
    }
    (a as i64)..=(b as i64)
}

/// Distance from `p` to the segment `a`-`b`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (qx, qy) = (a[0] + t * dx, a[1] + t * dy);
    ((p[0] - qx).powi(2) + (p[1] - qy).powi(2)).sqrt()
}

/// A straight line from `from` to `to` (pixel coordinates), `thickness_px` wide, with round
/// caps and a one-pixel anti-aliased rim.
pub fn line(img: &mut RgbaImage, from: [f64; 2], to: [f64; 2], thickness_px: f64, rgba: [u8; 4]) {
    let half = 0.5 * thickness_px.max(0.0);
    let reach = half + 1.0;
    for y in pixel_range(
        from[1].min(to[1]) - reach,
        from[1].max(to[1]) + reach,
        img.height_px,
    ) {
        for x in pixel_range(
            from[0].min(to[0]) - reach,
            from[0].max(to[0]) + reach,
            img.width_px,
        ) {
            let centre = [x as f64 + 0.5, y as f64 + 0.5];
            let coverage = half + 0.5 - segment_distance(centre, from, to);
            blend_covered(img, x, y, rgba, coverage);
        }
    }
}

/// A filled disc of `radius_px` around `centre` with an anti-aliased rim.
pub fn disc(img: &mut RgbaImage, centre: [f64; 2], radius_px: f64, rgba: [u8; 4]) {
    let r = radius_px.max(0.0);
    for y in pixel_range(centre[1] - r - 1.0, centre[1] + r + 1.0, img.height_px) {
        for x in pixel_range(centre[0] - r - 1.0, centre[0] + r + 1.0, img.width_px) {
            let d = ((x as f64 + 0.5 - centre[0]).powi(2) + (y as f64 + 0.5 - centre[1]).powi(2))
                .sqrt();
            blend_covered(img, x, y, rgba, r + 0.5 - d);
        }
    }
}

/// A ring (circle outline) of `radius_px` around `centre`, `thickness_px` wide.
pub fn ring(
    img: &mut RgbaImage,
    centre: [f64; 2],
    radius_px: f64,
    thickness_px: f64,
    rgba: [u8; 4],
) {
    let half = 0.5 * thickness_px.max(0.0);
    let outer = radius_px.max(0.0) + half;
    for y in pixel_range(
        centre[1] - outer - 1.0,
        centre[1] + outer + 1.0,
        img.height_px,
    ) {
        for x in pixel_range(
            centre[0] - outer - 1.0,
            centre[0] + outer + 1.0,
            img.width_px,
        ) {
            let d = ((x as f64 + 0.5 - centre[0]).powi(2) + (y as f64 + 0.5 - centre[1]).powi(2))
                .sqrt();
            blend_covered(img, x, y, rgba, half + 0.5 - (d - radius_px).abs());
        }
    }
}

/// A filled axis-aligned rectangle with its top-left pixel at (`x`, `y`).
pub fn fill_rect(
    img: &mut RgbaImage,
    x: i32,
    y: i32,
    width_px: u32,
    height_px: u32,
    rgba: [u8; 4],
) {
    let (x0, y0) = (i64::from(x), i64::from(y));
    for py in y0.max(0)..(y0 + i64::from(height_px)).min(i64::from(img.height_px)) {
        for px in x0.max(0)..(x0 + i64::from(width_px)).min(i64::from(img.width_px)) {
            blend_covered(img, px, py, rgba, 1.0);
        }
    }
}

/// The outline of the rectangle with top-left pixel (`x`, `y`) and the given size, drawn
/// `thickness_px` wide inside it.
pub fn rect_outline(
    img: &mut RgbaImage,
    x: i32,
    y: i32,
    width_px: u32,
    height_px: u32,
    thickness_px: u32,
    rgba: [u8; 4],
) {
    let t = thickness_px
        .min(width_px.div_ceil(2))
        .min(height_px.div_ceil(2));
    let right = x.saturating_add_unsigned(width_px.saturating_sub(t));
    let bottom = y.saturating_add_unsigned(height_px.saturating_sub(t));
    let inner_h = height_px.saturating_sub(2 * t);
    fill_rect(img, x, y, width_px, t, rgba);
    fill_rect(img, x, bottom, width_px, t, rgba);
    fill_rect(img, x, y.saturating_add_unsigned(t), t, inner_h, rgba);
    fill_rect(img, right, y.saturating_add_unsigned(t), t, inner_h, rgba);
}

/// Width and height in pixels of `text` drawn with [`text`] at `scale`.
#[must_use]
pub fn text_size(text: &str, scale: u32) -> (u32, u32) {
    let lines: Vec<&str> = text.split('\n').collect();
    let longest = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let longest = u32::try_from(longest).unwrap_or(u32::MAX);
    let width = if longest == 0 {
        0
    } else {
        (longest * ADVANCE - (ADVANCE - GLYPH_WIDTH)).saturating_mul(scale)
    };
    let rows = u32::try_from(lines.len()).unwrap_or(u32::MAX);
    let height = ((rows - 1) * LINE_ADVANCE + GLYPH_HEIGHT).saturating_mul(scale);
    (width, height)
}

/// Draws ASCII `text` with its top-left corner at (`x`, `y`), each font cell `scale` x `scale`
/// pixels (`'\n'` starts a new line; other characters outside printable ASCII show as '?').
pub fn text(img: &mut RgbaImage, x: i32, y: i32, text: &str, scale: u32, rgba: [u8; 4]) {
    let scale = scale.max(1);
    let (mut cx, mut cy) = (i64::from(x), i64::from(y));
    let s = i64::from(scale);
    for c in text.chars() {
        if c == '\n' {
            cx = i64::from(x);
            cy += i64::from(LINE_ADVANCE) * s;
            continue;
        }
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..GLYPH_WIDTH {
                if bits & (0x10 >> col) == 0 {
                    continue;
                }
                let (px, py) = (cx + i64::from(col) * s, cy + row as i64 * s);
                for dy in 0..s {
                    for dx in 0..s {
                        blend_covered(img, px + dx, py + dy, rgba, 1.0);
                    }
                }
            }
        }
        cx += i64::from(ADVANCE) * s;
    }
}

/// An arrow from `from` to `to`: a shaft `thickness_px` wide and a filled triangular head
/// `head_px` long (and as wide) whose tip is at `to`.
pub fn arrow(
    img: &mut RgbaImage,
    from: [f64; 2],
    to: [f64; 2],
    thickness_px: f64,
    head_px: f64,
    rgba: [u8; 4],
) {
    let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
    let len = (dx * dx + dy * dy).sqrt();
    if len.is_nan() || len <= 0.0 {
        disc(img, to, 0.5 * thickness_px, rgba);
        return;
    }
    let (ux, uy) = (dx / len, dy / len);
    let head = head_px.clamp(0.0, len);
    let base = [to[0] - ux * head, to[1] - uy * head];
    line(img, from, base, thickness_px, rgba);
    let half_w = 0.5 * head.max(thickness_px);
    let left = [base[0] - uy * half_w, base[1] + ux * half_w];
    let right = [base[0] + uy * half_w, base[1] - ux * half_w];
    fill_triangle(img, [to, left, right], rgba);
}

/// A filled triangle (pixel centres inside, no anti-aliasing).
pub fn fill_triangle(img: &mut RgbaImage, corners: [[f64; 2]; 3], rgba: [u8; 4]) {
    let [a, b, c] = corners;
    let cross = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    let area = cross(a, b, c);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let s = area.signum();
    let min_x = a[0].min(b[0]).min(c[0]);
    let max_x = a[0].max(b[0]).max(c[0]);
    let min_y = a[1].min(b[1]).min(c[1]);
    let max_y = a[1].max(b[1]).max(c[1]);
    for y in pixel_range(min_y, max_y, img.height_px) {
        for x in pixel_range(min_x, max_x, img.width_px) {
            let p = [x as f64 + 0.5, y as f64 + 0.5];
            if s * cross(a, b, p) >= 0.0 && s * cross(b, c, p) >= 0.0 && s * cross(c, a, p) >= 0.0 {
                blend_covered(img, x, y, rgba, 1.0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: [u8; 4] = [255, 0, 0, 255];
    const WHITE: [u8; 4] = [255, 255, 255, 255];

    fn drawn(img: &RgbaImage) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for y in 0..img.height_px {
            for x in 0..img.width_px {
                if img.get(x, y) != WHITE {
                    out.push((x, y));
                }
            }
        }
        out
    }

    #[test]
    fn text_stays_in_its_glyph_box_and_draws_the_glyph_shape() {
        let mut img = RgbaImage::new(60, 30, WHITE);
        text(&mut img, 3, 4, "Hi", 2, RED);
        let (w, h) = text_size("Hi", 2);
        assert_eq!((w, h), (22, 14));
        let px = drawn(&img);
        assert!(!px.is_empty());
        assert!(
            px.iter()
                .all(|&(x, y)| (3..3 + w).contains(&x) && (4..4 + h).contains(&y))
        );
        // 'H': the left column of the glyph is fully on, the top of its middle column is off.
        for row in 0..7 {
            assert_eq!(img.get(3, 4 + 2 * row), RED);
        }
        assert_eq!(img.get(3 + 2 * 2, 4), WHITE);
        // 'H' has 17 lit cells and 'i' has 9: each cell is 2x2 pixels.
        assert_eq!(px.len(), (17 + 9) * 4);
    }

    #[test]
    fn line_and_disc_cover_their_shapes_only() {
        let mut img = RgbaImage::new(40, 40, WHITE);
        line(&mut img, [5.0, 20.0], [35.0, 20.0], 3.0, RED);
        assert_eq!(img.get(20, 19), RED);
        assert_eq!(img.get(20, 20), RED);
        assert_eq!(img.get(20, 10), WHITE);
        assert!(drawn(&img).iter().all(|&(_, y)| (17..=22).contains(&y)));
        let mut img = RgbaImage::new(40, 40, WHITE);
        disc(&mut img, [20.0, 20.0], 6.0, RED);
        assert_eq!(img.get(20, 20), RED);
        assert_eq!(img.get(24, 20), RED);
        for (x, y) in drawn(&img) {
            let d =
                ((f64::from(x) + 0.5 - 20.0).powi(2) + (f64::from(y) + 0.5 - 20.0).powi(2)).sqrt();
            assert!(d < 6.6, "({x}, {y}) at {d}");
        }
    }

    #[test]
    fn arrow_head_is_at_the_tip_and_rect_outline_leaves_the_inside() {
        let mut img = RgbaImage::new(50, 50, WHITE);
        arrow(&mut img, [5.0, 25.0], [45.0, 25.0], 2.0, 10.0, RED);
        // The head is wider than the shaft near its base.
        assert_eq!(img.get(37, 21), RED);
        assert_eq!(img.get(15, 21), WHITE);
        assert_eq!(img.get(47, 25), WHITE);
        let mut img = RgbaImage::new(20, 20, WHITE);
        rect_outline(&mut img, 2, 3, 10, 8, 2, RED);
        assert_eq!(img.get(2, 3), RED);
        assert_eq!(img.get(11, 10), RED);
        assert_eq!(img.get(6, 6), WHITE);
        assert_eq!(img.get(12, 3), WHITE);
        assert_eq!(drawn(&img).len(), 10 * 8 - 6 * 4);
    }
}
