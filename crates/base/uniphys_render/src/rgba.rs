/// An 8-bit RGBA image, row-major from the top-left, straight (not premultiplied) alpha.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width_px: u32,
    /// Height in pixels.
    pub height_px: u32,
    /// `width_px * height_px` pixels, row by row.
    pub pixels: Vec<[u8; 4]>,
}

impl RgbaImage {
    /// An image filled with `fill`.
    #[must_use]
    pub fn new(width_px: u32, height_px: u32, fill: [u8; 4]) -> Self {
        Self {
            width_px,
            height_px,
            pixels: vec![fill; width_px as usize * height_px as usize],
        }
    }

    fn index(&self, x: u32, y: u32) -> Option<usize> {
        (x < self.width_px && y < self.height_px)
            .then(|| y as usize * self.width_px as usize + x as usize)
    }

    /// The pixel at (`x`, `y`); transparent black outside the image.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> [u8; 4] {
        self.index(x, y)
            .and_then(|i| self.pixels.get(i).copied())
            .unwrap_or([0; 4])
    }

    /// Sets the pixel at (`x`, `y`); ignored outside the image.
    pub fn put(&mut self, x: u32, y: u32, rgba: [u8; 4]) {
        if let Some(p) = self.index(x, y).and_then(|i| self.pixels.get_mut(i)) {
            *p = rgba;
        }
    }

    /// Composites `rgba` over the pixel at (`x`, `y`) (straight-alpha source-over); ignored
    /// outside the image.
    pub fn blend(&mut self, x: u32, y: u32, rgba: [u8; 4]) {
        if let Some(p) = self.index(x, y).and_then(|i| self.pixels.get_mut(i)) {
            *p = over(rgba, *p);
        }
    }

    /// Copies `src` with its top-left corner at (`x`, `y`) (pixels replaced, clipped to this image).
    pub fn blit(&mut self, src: &RgbaImage, x: u32, y: u32) {
        for sy in 0..src.height_px {
            for sx in 0..src.width_px {
                self.put(x.saturating_add(sx), y.saturating_add(sy), src.get(sx, sy));
            }
        }
    }

    /// Composites `src` over this image with its top-left corner at (`x`, `y`).
    pub fn blit_over(&mut self, src: &RgbaImage, x: u32, y: u32) {
        for sy in 0..src.height_px {
            for sx in 0..src.width_px {
                self.blend(x.saturating_add(sx), y.saturating_add(sy), src.get(sx, sy));
            }
        }
    }

    /// This image composited over an opaque `background` colour (alpha of the result is 255).
    #[must_use]
    pub fn flattened(&self, background: [u8; 3]) -> RgbaImage {
        let bg = [background[0], background[1], background[2], 255];
        RgbaImage {
            width_px: self.width_px,
            height_px: self.height_px,
            pixels: self.pixels.iter().map(|&p| over(p, bg)).collect(),
        }
    }

    /// The image shrunk by an integer `factor`, each output pixel the mean of a `factor` x
    /// `factor` block (alpha-weighted colour; partial blocks at the right and bottom edges are
    /// dropped). `factor` 0 or 1 returns a copy.
    #[must_use]
    pub fn downsampled(&self, factor: u32) -> RgbaImage {
        if factor <= 1 {
            return self.clone();
        }
        let (w, h) = (self.width_px / factor, self.height_px / factor);
        let mut out = RgbaImage::new(w, h, [0; 4]);
        let n = u64::from(factor * factor);
        for y in 0..h {
            for x in 0..w {
                let (mut rgb, mut alpha) = ([0u64; 3], 0u64);
                for dy in 0..factor {
                    for dx in 0..factor {
                        let p = self.get(x * factor + dx, y * factor + dy);
                        let a = u64::from(p[3]);
                        for c in 0..3 {
                            rgb[c] += u64::from(p[c]) * a;
                        }
                        alpha += a;
                    }
                }
                let colour = |sum: u64| {
                    (sum + alpha / 2)
                        .checked_div(alpha)
                        .map_or(0, |c| u8::try_from(c).unwrap_or(255))
                };
                let a = u8::try_from((alpha + n / 2) / n).unwrap_or(255);
                out.put(x, y, [colour(rgb[0]), colour(rgb[1]), colour(rgb[2]), a]);
            }
        }
        out
    }

    /// Number of pixels exactly equal to `rgba`.
    #[must_use]
    pub fn count(&self, rgba: [u8; 4]) -> usize {
        self.pixels.iter().filter(|&&p| p == rgba).count()
    }
}

/// Straight-alpha source-over: `src` over `dst`.
#[must_use]
pub fn over(src: [u8; 4], dst: [u8; 4]) -> [u8; 4] {
    let sa = u32::from(src[3]);
    if sa == 255 {
        return src;
    }
    if sa == 0 {
        return dst;
    }
    let da = u32::from(dst[3]);
    // All in units of 1/255 (alpha) and 1/65025 (colour x alpha), rounded to nearest.
    let da_rest = da * (255 - sa); // / 255^2
    let out_a2 = sa * 255 + da_rest; // alpha * 255^2
    let mut out = [0u8; 4];
    for c in 0..3 {
        let num = u32::from(src[c]) * sa * 255 + u32::from(dst[c]) * da_rest;
        out[c] = u8::try_from((num + out_a2 / 2) / out_a2).unwrap_or(255);
    }
    out[3] = u8::try_from((out_a2 + 127) / 255).unwrap_or(255);
    out
}

/// The images side by side, top-aligned, `gap_px` apart, on `background`.
#[must_use]
pub fn hstack(images: &[RgbaImage], gap_px: u32, background: [u8; 4]) -> RgbaImage {
    let gaps = gap_px.saturating_mul(u32::try_from(images.len().saturating_sub(1)).unwrap_or(0));
    let width = images
        .iter()
        .fold(gaps, |w, im| w.saturating_add(im.width_px));
    let height = images.iter().map(|im| im.height_px).max().unwrap_or(0);
    let mut out = RgbaImage::new(width, height, background);
    let mut x = 0u32;
    for im in images {
        out.blit(im, x, 0);
        x = x.saturating_add(im.width_px).saturating_add(gap_px);
    }
    out
}

/// The images one above the other, left-aligned, `gap_px` apart, on `background`.
#[must_use]
pub fn vstack(images: &[RgbaImage], gap_px: u32, background: [u8; 4]) -> RgbaImage {
    let gaps = gap_px.saturating_mul(u32::try_from(images.len().saturating_sub(1)).unwrap_or(0));
    let height = images
        .iter()
        .fold(gaps, |h, im| h.saturating_add(im.height_px));
    let width = images.iter().map(|im| im.width_px).max().unwrap_or(0);
    let mut out = RgbaImage::new(width, height, background);
    let mut y = 0u32;
    for im in images {
        out.blit(im, 0, y);
        y = y.saturating_add(im.height_px).saturating_add(gap_px);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn get_put_blend_respect_bounds_and_alpha() {
        let mut im = RgbaImage::new(3, 2, [0, 0, 255, 255]);
        im.put(2, 1, [1, 2, 3, 4]);
        assert_eq!(im.get(2, 1), [1, 2, 3, 4]);
        assert_eq!(im.pixels[5], [1, 2, 3, 4]);
        im.put(3, 0, [9; 4]); // outside: ignored
        assert_eq!(im.get(3, 0), [0; 4]);
        im.blend(0, 0, [255, 0, 0, 128]);
        let p = im.get(0, 0);
        assert_eq!(p[3], 255);
        assert!(
            (i32::from(p[0]) - 128).abs() <= 1 && (i32::from(p[2]) - 127).abs() <= 1,
            "{p:?}"
        );
        // Over a transparent pixel the source colour is kept whatever its alpha.
        assert_eq!(over([10, 20, 30, 40], [0; 4]), [10, 20, 30, 40]);
        assert_eq!(over([10, 20, 30, 0], [5, 6, 7, 8]), [5, 6, 7, 8]);
    }

    #[test]
    fn downsampling_averages_blocks_weighted_by_alpha() {
        let mut im = RgbaImage::new(4, 2, [255, 255, 255, 255]);
        im.put(0, 0, [0, 0, 0, 255]);
        im.put(2, 0, [200, 0, 0, 0]); // transparent: no colour contribution
        let d = im.downsampled(2);
        assert_eq!((d.width_px, d.height_px), (2, 1));
        assert_eq!(d.get(0, 0), [191, 191, 191, 255]);
        assert_eq!(d.get(1, 0), [255, 255, 255, 191]);
        assert_eq!(im.downsampled(1), im);
    }

    #[test]
    fn hstack_places_images_with_gaps() {
        let a = RgbaImage::new(2, 3, [255, 0, 0, 255]);
        let b = RgbaImage::new(4, 1, [0, 255, 0, 255]);
        let s = hstack(&[a, b], 5, [0, 0, 0, 0]);
        assert_eq!((s.width_px, s.height_px), (11, 3));
        assert_eq!(s.get(1, 2), [255, 0, 0, 255]);
        assert_eq!(s.get(3, 0), [0, 0, 0, 0]);
        assert_eq!(s.get(7, 0), [0, 255, 0, 255]);
        assert_eq!(s.get(7, 1), [0, 0, 0, 0]);
        let v = vstack(&[s.clone(), s], 1, [9, 9, 9, 9]);
        assert_eq!((v.width_px, v.height_px), (11, 7));
        assert_eq!(v.get(0, 3), [9, 9, 9, 9]);
        assert_eq!(v.get(0, 4), [255, 0, 0, 255]);
    }
}
