use crate::Texture;

/// Converts a linear colour component in [0, 1] to an 8-bit sRGB value (clamped).
#[must_use]
pub fn linear_to_srgb8(linear: f32) -> u8 {
    let c = f64::from(linear).clamp(0.0, 1.0);
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0).round().clamp(0.0, 255.0) as u8
}

/// Converts an 8-bit sRGB value to a linear component in [0, 1].
#[must_use]
pub fn srgb8_to_linear(srgb: u8) -> f32 {
    let c = f64::from(srgb) / 255.0;
    let linear = if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    linear as f32
}

/// The texel under `uv` (glTF convention: v = 0 is the top row), nearest pixel, repeating
/// outside [0, 1), with its alpha. `None` for an empty or malformed texture or a non-finite UV.
#[must_use]
pub fn texel_rgba8(texture: &Texture, uv: [f32; 2]) -> Option<[u8; 4]> {
    let (w, h) = (texture.width as usize, texture.height as usize);
    if w == 0 || h == 0 || texture.rgba8.len() < w * h * 4 || !uv.iter().all(|c| c.is_finite()) {
        return None;
    }
    let wrap = |c: f32, n: usize| {
        let c = f64::from(c);
        let frac = c - c.floor();
        ((frac * n as f64) as usize).min(n - 1)
    };
    let at = (wrap(uv[1], h) * w + wrap(uv[0], w)) * 4;
    let px = texture.rgba8.get(at..at + 4)?;
    Some([px[0], px[1], px[2], px[3]])
}

/// [`texel_rgba8`] without the alpha.
pub(crate) fn texel_rgb8(texture: &Texture, uv: [f32; 2]) -> Option<[u8; 3]> {
    texel_rgba8(texture, uv).map(|[r, g, b, _]| [r, g, b])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_matches_reference_points() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        // Linear 0.5 is sRGB 0.7354 -> 187.5 -> 188; 128 covers linear (0.2140, 0.2177).
        assert_eq!(linear_to_srgb8(0.5), 188);
        assert_eq!(linear_to_srgb8(0.2159), 128);
        assert_eq!(linear_to_srgb8(2.0), 255);
        for v in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb8_to_linear(v)), v);
        }
    }

    #[test]
    fn texel_lookup_uses_v_down_nearest_pixel_and_repeats() {
        // 2 x 2 image: top row red, green; bottom row blue, white.
        let texture = Texture {
            name: "t".to_owned(),
            width: 2,
            height: 2,
            rgba8: vec![
                255, 0, 0, 255, 0, 255, 0, 255, //
                0, 0, 255, 255, 255, 255, 255, 255,
            ],
        };
        assert_eq!(texel_rgb8(&texture, [0.25, 0.25]), Some([255, 0, 0]));
        assert_eq!(texel_rgb8(&texture, [0.75, 0.25]), Some([0, 255, 0]));
        assert_eq!(texel_rgb8(&texture, [0.25, 0.75]), Some([0, 0, 255]));
        // Repeat: u = 1.75 is 0.75, v = -0.25 is 0.75.
        assert_eq!(texel_rgb8(&texture, [1.75, -0.25]), Some([255, 255, 255]));
        assert_eq!(texel_rgb8(&texture, [f32::NAN, 0.0]), None);
    }
}
