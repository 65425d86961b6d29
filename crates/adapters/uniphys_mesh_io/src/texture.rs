//! Decoding of texture images (PNG, JPEG) to RGBA8, with size limits and a panic guard.

use std::io::Cursor;
use std::path::Path;

use uniphys_geometry::Texture;

use crate::guard::guarded;
use crate::{IngestError, IngestResult};

/// Largest accepted texture side, pixels.
const MAX_SIDE: u32 = 16_384;
/// Largest decoder allocation, bytes.
const MAX_ALLOC: u64 = 1 << 30;

/// Decodes `bytes` (the image named `name`, found in or referenced by `path`) to RGBA8.
pub(crate) fn decode_texture(path: &Path, name: &str, bytes: &[u8]) -> IngestResult<Texture> {
    let fail =
        |message: String| IngestError::parse(path, "image", format!("texture {name:?}: {message}"));
    let decoded = guarded(path, "image", || {
        let mut reader = image::ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_SIDE);
        limits.max_image_height = Some(MAX_SIDE);
        limits.max_alloc = Some(MAX_ALLOC);
        reader.limits(limits);
        reader.decode().map_err(|e| e.to_string())
    })?
    .map_err(fail)?;
    let rgba = decoded.to_rgba8();
    Ok(Texture {
        name: name.to_owned(),
        width: rgba.width(),
        height: rgba.height(),
        rgba8: rgba.into_raw(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_decodes_to_rgba8_pixels() {
        let img = image::RgbImage::from_pixel(2, 1, image::Rgb([10, 20, 30]));
        let mut png = Vec::new();
        img.write_to(&mut Cursor::new(&mut png), image::ImageFormat::Png)
            .expect("encode");
        let t = decode_texture(Path::new("a.gltf"), "t.png", &png).expect("decodes");
        assert_eq!((t.width, t.height), (2, 1));
        assert_eq!(t.rgba8, vec![10, 20, 30, 255, 10, 20, 30, 255]);
    }

    #[test]
    fn garbage_image_is_a_parse_error_naming_file_and_texture() {
        let err = decode_texture(Path::new("a.mtl"), "wood.png", b"not an image").expect_err("bad");
        let msg = err.to_string();
        assert!(msg.contains("a.mtl") && msg.contains("wood.png"), "{msg}");
    }
}
