/// Errors of the renderer.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// An image has no pixels (PNG needs a positive width and height).
    #[error("cannot encode an empty image ({width_px}x{height_px} px)")]
    EmptyImage {
        /// Width in pixels.
        width_px: u32,
        /// Height in pixels.
        height_px: u32,
    },
    /// An image's pixel buffer does not match its size.
    #[error("image of {width_px}x{height_px} px holds {pixels} pixels")]
    PixelCountMismatch {
        /// Width in pixels.
        width_px: u32,
        /// Height in pixels.
        height_px: u32,
        /// Pixels in the buffer.
        pixels: usize,
    },
    /// The PNG encoder failed.
    #[error("PNG encoding failed: {0}")]
    PngEncode(#[from] png::EncodingError),
    /// The PNG decoder failed.
    #[error("PNG decoding failed: {0}")]
    PngDecode(#[from] png::DecodingError),
    /// A decoded PNG is not 8-bit RGBA or RGB.
    #[error("unsupported PNG layout: {0}")]
    UnsupportedPng(String),
}

/// Result of the renderer's fallible functions.
pub type RenderResult<T> = Result<T, RenderError>;
