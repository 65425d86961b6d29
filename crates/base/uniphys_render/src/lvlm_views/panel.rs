//! Titled, framed panels and colour legends.

use super::colours::{FRAME, INK, WHITE};
use crate::draw;
use crate::rgba::RgbaImage;

/// Padding around titles and legend rows, in font cells.
const PAD_CELLS: u32 = 2;

/// Font scale for a panel `panel_px` wide: the 5x7 font at 1 px per cell up to 191 px panels,
/// 2 px per cell up to 383 px, and so on.
pub(crate) fn font_scale(panel_px: u32) -> u32 {
    (panel_px / 192).max(1)
}

/// `body` under a centred `title`, framed in red, with an optional `legend` under it; white
/// background.
pub(crate) fn titled_panel(
    title: &str,
    body: &RgbaImage,
    legend: Option<&RgbaImage>,
    scale: u32,
) -> RgbaImage {
    let legend_h = legend.map_or(0, |l| l.height_px);
    let width = body.width_px.max(legend.map_or(0, |l| l.width_px));
    let pad = PAD_CELLS * scale;
    // Titles that do not fit are wrapped at spaces; a smaller font only if a word is too long.
    let mut title_scale = scale.max(1);
    let mut lines = wrap(title, width.saturating_sub(2 * pad), title_scale);
    while title_scale > 1
        && lines
            .iter()
            .any(|l| draw::text_size(l, title_scale).0 + 2 * pad > width)
    {
        title_scale -= 1;
        lines = wrap(title, width.saturating_sub(2 * pad), title_scale);
    }
    let line_h = draw::LINE_ADVANCE * title_scale;
    let rows = u32::try_from(lines.len()).unwrap_or(1).max(1);
    let title_h = (rows - 1) * line_h + draw::GLYPH_HEIGHT * scale + 2 * pad;
    let mut out = RgbaImage::new(width, title_h + body.height_px + legend_h, WHITE);
    for (row, line) in (0u32..).zip(&lines) {
        let (text_w, _) = draw::text_size(line, title_scale);
        let text_x = i32::try_from(width.saturating_sub(text_w) / 2).unwrap_or(0);
        let text_y = i32::try_from(pad + row * line_h).unwrap_or(0);
        draw::text(&mut out, text_x, text_y, line, title_scale, INK);
    }
    out.blit(body, 0, title_h);
    draw::rect_outline(
        &mut out,
        0,
        i32::try_from(title_h).unwrap_or(0),
        body.width_px,
        body.height_px,
        scale.max(2),
        FRAME,
    );
    if let Some(legend) = legend {
        out.blit(legend, 0, title_h + body.height_px);
    }
    out
}

/// A legend `width_px` wide: for each entry a colour swatch (dark outline) and its text,
/// wrapped into rows.
pub(crate) fn legend(entries: &[(String, [u8; 4])], width_px: u32, scale: u32) -> RgbaImage {
    let pad = PAD_CELLS * scale;
    let swatch = draw::GLYPH_HEIGHT * scale;
    let row_h = swatch + pad;
    // Place entries left to right, wrapping.
    let mut placed = Vec::with_capacity(entries.len());
    let (mut x, mut row) = (pad, 0u32);
    for (label, rgba) in entries {
        let (text_w, _) = draw::text_size(label, scale);
        let entry_w = swatch + scale * 2 + text_w;
        if x > pad && x + entry_w > width_px.saturating_sub(pad) {
            x = pad;
            row += 1;
        }
        placed.push((x, row, label, *rgba));
        x += entry_w + 4 * scale;
    }
    let rows = if entries.is_empty() { 0 } else { row + 1 };
    let mut out = RgbaImage::new(width_px, rows * row_h + pad, WHITE);
    for (x, row, label, rgba) in placed {
        let y = pad + row * row_h;
        let (xi, yi) = (i32::try_from(x).unwrap_or(0), i32::try_from(y).unwrap_or(0));
        draw::fill_rect(&mut out, xi, yi, swatch, swatch, rgba);
        draw::rect_outline(&mut out, xi, yi, swatch, swatch, 1, INK);
        let tx = xi.saturating_add_unsigned(swatch + 2 * scale);
        draw::text(&mut out, tx, yi, label, scale, INK);
    }
    out
}

/// `text` split at spaces into lines at most `width_px` wide at `scale` (a longer word gets a
/// line of its own).
fn wrap(text: &str, width_px: u32, scale: u32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if draw::text_size(&format!("{line} {word}"), scale).0 <= width_px => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_titles_wrap_at_spaces_and_stay_inside_the_panel() {
        let lines = wrap("Candidate pivot points (camera view 0)", 300, 2);
        assert_eq!(lines, vec!["Candidate pivot points", "(camera view 0)"]);
        let body = RgbaImage::new(300, 50, [0, 0, 255, 255]);
        let one = titled_panel("short", &body, None, 2);
        let two = titled_panel("Candidate pivot points (camera view 0)", &body, None, 2);
        assert_eq!(two.height_px - one.height_px, draw::LINE_ADVANCE * 2);
        // Ink only inside the panel's width, above the framed body.
        let title_h = two.height_px - 50;
        let inked = (0..title_h)
            .flat_map(|y| (0..300).map(move |x| (x, y)))
            .filter(|&(x, y)| two.get(x, y) == INK)
            .count();
        assert!(inked > 100);
        assert_eq!(two.get(150, title_h + 25), [0, 0, 255, 255]);
        assert_eq!(two.get(0, title_h + 25), FRAME);
    }
}
