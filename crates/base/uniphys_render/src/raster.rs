//! The triangle scan converter behind [`crate::render_face_ids`].

use uniphys_geometry::DVec3;

use crate::camera::ViewTransform;

/// A vertex in pixel coordinates with its inverse view depth (interpolates linearly on screen).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScreenVertex {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) inv_z: f64,
}

impl ScreenVertex {
    /// Projects a view-space point; only meaningful in front of the near plane.
    #[inline]
    pub(crate) fn project(view: &ViewTransform, p_view: DVec3) -> Self {
        let (x, y) = view.screen(p_view);
        Self {
            x,
            y,
            inv_z: 1.0 / p_view.z,
        }
    }
}

/// The buffers a triangle is drawn into.
pub(crate) struct Target<'a> {
    pub(crate) width_px: usize,
    pub(crate) height_px: usize,
    /// Inverse view depth per pixel, 0 on background.
    pub(crate) inv_depth: &'a mut [f32],
    /// Face id per pixel, 0 on background.
    pub(crate) face: &'a mut [u32],
}

/// An edge function `E(p) = sign * ((q - p0) x (p - p0))` evaluated with its endpoints in a
/// canonical order (smaller `(y, x)` first), so the two triangles sharing an edge compute exactly
/// opposite values and a pixel centre on the edge goes to exactly one of them.
#[derive(Debug, Clone, Copy)]
struct Edge {
    ax: f64,
    ay: f64,
    dx: f64,
    dy: f64,
    sign: f64,
}

impl Edge {
    #[inline]
    fn new(a: ScreenVertex, b: ScreenVertex) -> Self {
        let (p, q, sign) = if (a.y, a.x) <= (b.y, b.x) {
            (a, b, 1.0)
        } else {
            (b, a, -1.0)
        };
        Self {
            ax: p.x,
            ay: p.y,
            dx: q.x - p.x,
            dy: q.y - p.y,
            sign,
        }
    }

    /// The part of `E` that depends only on the row.
    #[inline]
    fn row(&self, y: f64) -> f64 {
        self.dx * (y - self.ay)
    }

    #[inline]
    fn at(&self, row: f64, x: f64) -> f64 {
        self.sign * (row - self.dy * (x - self.ax))
    }

    /// Inside test with the ownership rule for centres exactly on the edge.
    #[inline]
    fn covers(&self, value: f64) -> bool {
        value > 0.0 || (value == 0.0 && self.sign > 0.0)
    }
}

/// Draws one screen-space triangle with face id `id` into `target` (z-test on inverse depth,
/// strictly nearer wins, so on a tie the earlier, smaller id stays).
pub(crate) fn rasterise_triangle(target: &mut Target<'_>, v: [ScreenVertex; 3], id: u32) {
    rasterise(target, v, id, true);
}

/// Bounding boxes at least this wide (and mostly empty) are scanned row by row only over the
/// span where the edge functions can be non-negative (found analytically, widened by a pixel each
/// side; the exact test still decides each pixel), so long thin triangles cost their area, not
/// their box.
const SPAN_MIN_WIDTH_PX: usize = 3;

/// [`rasterise_triangle`]; `use_spans` off scans the whole bounding box (for tests).
fn rasterise(target: &mut Target<'_>, v: [ScreenVertex; 3], id: u32, use_spans: bool) {
    let min_x = v[0].x.min(v[1].x).min(v[2].x);
    let max_x = v[0].x.max(v[1].x).max(v[2].x);
    let min_y = v[0].y.min(v[1].y).min(v[2].y);
    let max_y = v[0].y.max(v[1].y).max(v[2].y);
    // Pixel i is covered when its centre i + 0.5 is inside: i in [ceil(min - 0.5), floor(max - 0.5)].
    if !(min_x.is_finite() && max_x.is_finite() && min_y.is_finite() && max_y.is_finite()) {
        return;
    }
    let x0 = ceil(min_x - 0.5).max(0.0);
    let y0 = ceil(min_y - 0.5).max(0.0);
    let x1 = floor(max_x - 0.5).min(target.width_px as f64 - 1.0);
    let y1 = floor(max_y - 0.5).min(target.height_px as f64 - 1.0);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let mut e = [
        Edge::new(v[1], v[2]),
        Edge::new(v[2], v[0]),
        Edge::new(v[0], v[1]),
    ];
    let mut area = e[2].at(e[2].row(v[2].y), v[2].x);
    if !area.is_finite() || area == 0.0 {
        return;
    }
    if area < 0.0 {
        // Both sides are visible: reverse the traversal so the inside is positive.
        for edge in &mut e {
            edge.sign = -edge.sign;
        }
        area = -area;
    }
    let inv_area = 1.0 / area;
    let (z0, z1, z2) = (
        v[0].inv_z * inv_area,
        v[1].inv_z * inv_area,
        v[2].inv_z * inv_area,
    );
    let (x0, x1, y0, y1) = (x0 as usize, x1 as usize, y0 as usize, y1 as usize);
    let width = target.width_px;
    let first_row_y = y0 as f64 + 0.5;
    // `area` is twice the triangle's area in pixels: spans pay off when the box is mostly empty.
    let box_px = ((x1 - x0 + 1) * (y1 - y0 + 1)) as f64;
    let roots = (use_spans && x1 - x0 >= SPAN_MIN_WIDTH_PX && box_px > area + 32.0)
        .then(|| e.map(|edge| EdgeRoot::new(&edge, first_row_y)));
    for y in y0..=y1 {
        let fy = y as f64 + 0.5;
        let r = [e[0].row(fy), e[1].row(fy), e[2].row(fy)];
        let row_start = y * width;
        let (mut lo, mut hi) = (x0, x1);
        if let Some(roots) = &roots {
            let Some((a, b)) = row_span(&e, roots, &r, y - y0, x0, x1) else {
                continue;
            };
            (lo, hi) = (a, b);
        }
        for x in lo..=hi {
            let fx = x as f64 + 0.5;
            let w0 = e[0].at(r[0], fx);
            let w1 = e[1].at(r[1], fx);
            let w2 = e[2].at(r[2], fx);
            if !(e[0].covers(w0) && e[1].covers(w1) && e[2].covers(w2)) {
                continue;
            }
            let inv_z = (w0 * z0 + w1 * z1 + w2 * z2) as f32;
            let k = row_start + x;
            if inv_z > target.inv_depth[k] {
                target.inv_depth[k] = inv_z;
                target.face[k] = id;
            }
        }
    }
}

/// Where an edge function changes sign along a row, as a linear function of the row.
#[derive(Debug, Clone, Copy)]
struct EdgeRoot {
    /// Pixel coordinate (centre at `i`) where E = 0 on the first row of the box.
    root_first_row: f64,
    /// Change of that coordinate per row.
    root_per_row: f64,
    /// E grows to the right (the inside is right of the root), else to the left.
    rising: bool,
    /// The edge is horizontal: E is constant along a row.
    horizontal: bool,
}

impl EdgeRoot {
    fn new(edge: &Edge, first_row_y: f64) -> Self {
        // E(fx) = sign * (row - dy * (fx - ax)) with row = dx * (fy - ay): slope -sign * dy,
        // zero at fx = ax + dx * (fy - ay) / dy.
        let slope = -edge.sign * edge.dy;
        let horizontal = slope == 0.0;
        let root_per_row = if horizontal { 0.0 } else { edge.dx / edge.dy };
        Self {
            root_first_row: if horizontal {
                0.0
            } else {
                edge.ax + (first_row_y - edge.ay) * root_per_row - 0.5
            },
            root_per_row,
            rising: slope > 0.0,
            horizontal,
        }
    }
}

/// Pixel range of row `row_index` (counted from the box's first row, within `x0..=x1`) outside
/// of which some edge function is negative, widened by one pixel each side against rounding;
/// `None` when the whole row is outside.
fn row_span(
    e: &[Edge; 3],
    roots: &[EdgeRoot; 3],
    r: &[f64; 3],
    row_index: usize,
    x0: usize,
    x1: usize,
) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (x0 as f64, x1 as f64);
    for ((edge, root), &row) in e.iter().zip(roots).zip(r) {
        if root.horizontal {
            if edge.sign * row < 0.0 {
                return None;
            }
            continue;
        }
        let at = root.root_first_row + root.root_per_row * row_index as f64;
        if root.rising {
            lo = lo.max(floor(at.max(-1e15)) - 1.0);
        } else {
            hi = hi.min(ceil(at.min(1e15)) + 1.0);
        }
    }
    (lo <= hi).then_some((lo as usize, hi as usize))
}

/// `v.ceil()` for finite `v` without a libm call (baseline x86-64 has no rounding instruction);
/// values beyond the `i64` range saturate, which the callers clamp to the image anyway.
#[inline]
fn ceil(v: f64) -> f64 {
    let t = v as i64 as f64;
    if t < v { t + 1.0 } else { t }
}

/// `v.floor()` for finite `v`, as [`ceil`].
#[inline]
fn floor(v: f64) -> f64 {
    let t = v as i64 as f64;
    if t > v { t - 1.0 } else { t }
}

#[cfg(test)]
mod tests {
    use super::*;
    use uniphys_geometry::SplitMix64;

    #[test]
    fn row_spans_change_nothing_but_the_work() {
        let (w, h) = (97usize, 61usize);
        let mut rng = SplitMix64::new(11);
        let mut coord = |scale: f64| (rng.next_f64() * 1.4 - 0.2) * scale;
        let mut buffers = [
            (vec![0.0f32; w * h], vec![0u32; w * h]),
            (vec![0.0f32; w * h], vec![0u32; w * h]),
        ];
        for id in 1..=400u32 {
            let mut v = [ScreenVertex {
                x: 0.0,
                y: 0.0,
                inv_z: 0.0,
            }; 3];
            for p in &mut v {
                *p = ScreenVertex {
                    x: coord(w as f64),
                    y: coord(h as f64),
                    inv_z: 0.1 + coord(1.0).abs(),
                };
            }
            if id % 3 == 0 {
                // A long sliver: the third corner next to the second.
                v[2] = ScreenVertex {
                    x: v[1].x + 0.7,
                    y: v[1].y - 0.4,
                    inv_z: v[1].inv_z,
                };
            }
            for (use_spans, (depth, face)) in [false, true].into_iter().zip(buffers.iter_mut()) {
                let mut target = Target {
                    width_px: w,
                    height_px: h,
                    inv_depth: depth,
                    face,
                };
                rasterise(&mut target, v, id, use_spans);
            }
        }
        assert_eq!(buffers[0], buffers[1]);
        assert!(buffers[0].1.iter().filter(|&&f| f != 0).count() > w * h / 2);
    }

    #[test]
    fn fast_rounding_matches_the_standard_library() {
        for v in [
            -3.5,
            -3.0,
            -2.999,
            -0.5,
            -0.0,
            0.0,
            0.25,
            1.0,
            1.5,
            1e6 + 0.5,
            511.5,
        ] {
            assert_eq!(ceil(v), v.ceil(), "ceil {v}");
            assert_eq!(floor(v), v.floor(), "floor {v}");
        }
    }
}
