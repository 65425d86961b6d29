use std::path::PathBuf;

/// Errors of the example generator and the GLB writer.
#[derive(Debug, thiserror::Error)]
pub enum ExamplesError {
    /// A triangle's face material index points past the asset's material list.
    #[error(
        "part {part:?} triangle {triangle} uses material {material}, but the asset has {count}"
    )]
    MaterialOutOfRange {
        /// Name of the part.
        part: String,
        /// Index of the triangle in the part's mesh.
        triangle: usize,
        /// The out-of-range material index.
        material: u32,
        /// Number of materials in the asset.
        count: usize,
    },
    /// The binary buffer or a count does not fit the 32-bit sizes of a GLB file.
    #[error("the asset is too large for a GLB file ({what})")]
    TooLarge {
        /// What overflowed.
        what: &'static str,
    },
    /// The glTF document failed gltf-json's validation (a bug in the writer).
    #[error("generated glTF is invalid: {0}")]
    InvalidGltf(String),
    /// The glTF JSON could not be serialised.
    #[error("cannot serialise glTF JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// Reading or writing a file failed.
    #[error("I/O error on {path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}
