use crate::error::{RenderError, RenderResult};
use crate::rgba::RgbaImage;

/// The image as PNG bytes (8-bit RGBA, fixed compression and filter settings, no timestamps, so
/// the same image always gives the same bytes).
pub fn encode_png(image: &RgbaImage) -> RenderResult<Vec<u8>> {
    let (width_px, height_px) = (image.width_px, image.height_px);
    if width_px == 0 || height_px == 0 {
        return Err(RenderError::EmptyImage {
            width_px,
            height_px,
        });
    }
    if image.pixels.len() != width_px as usize * height_px as usize {
        return Err(RenderError::PixelCountMismatch {
            width_px,
            height_px,
            pixels: image.pixels.len(),
        });
    }
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width_px, height_px);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(image.pixels.as_flattened())?;
        writer.finish()?;
    }
    Ok(bytes)
}

/// Decodes an 8-bit RGB or RGBA PNG (RGB gets alpha 255).
pub fn decode_png(bytes: &[u8]) -> RenderResult<RgbaImage> {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info()?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| RenderError::UnsupportedPng("image too large".to_owned()))?;
    let mut buf = vec![0u8; size];
    let info = reader.next_frame(&mut buf)?;
    if info.bit_depth != png::BitDepth::Eight {
        return Err(RenderError::UnsupportedPng(format!(
            "bit depth {:?}",
            info.bit_depth
        )));
    }
    let data = buf.get(..info.buffer_size()).unwrap_or(&[]);
    let pixels: Vec<[u8; 4]> = match info.color_type {
        png::ColorType::Rgba => data
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect(),
        png::ColorType::Rgb => data
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        other => {
            return Err(RenderError::UnsupportedPng(format!(
                "colour type {other:?}"
            )));
        }
    };
    Ok(RgbaImage {
        width_px: info.width,
        height_px: info.height,
        pixels,
    })
}
