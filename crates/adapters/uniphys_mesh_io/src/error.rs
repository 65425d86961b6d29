//! The one error type of the crate. Every message names the file it is about and says what to fix.

use std::path::PathBuf;

use uniphys_geometry::GeometryError;

/// Why an input could not be ingested.
#[derive(Debug, thiserror::Error)]
pub enum IngestError {
    /// An [`crate::IngestOptions`] field has an unusable value.
    #[error("ingest option {option} is {value}; it must be {expected}")]
    InvalidOption {
        /// Name of the option.
        option: &'static str,
        /// The value given.
        value: String,
        /// The accepted values, in words.
        expected: &'static str,
    },
    /// A file could not be opened or read.
    #[error("cannot read {}: {source}; check that the file exists and is readable", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A file is larger than [`crate::IngestOptions::max_file_bytes`].
    #[error(
        "{} is {size} bytes, more than the limit of {limit} bytes; raise IngestOptions::max_file_bytes to load it",
        path.display()
    )]
    FileTooLarge {
        /// The file.
        path: PathBuf,
        /// Its size in bytes.
        size: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// A file has no bytes.
    #[error("{} is empty; provide a non-empty mesh file", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The input's extension is not one of the supported formats.
    #[error(
        "{} has the unsupported extension {extension:?}; supported are .glb, .gltf, .obj, .ply, .stl, .urdf, or a directory holding one .urdf file",
        path.display()
    )]
    UnsupportedFormat {
        /// The input path.
        path: PathBuf,
        /// Its extension (empty if it has none).
        extension: String,
    },
    /// A directory was given but it holds no `.urdf` file.
    #[error("directory {} holds no .urdf file; pass a mesh file or a folder with exactly one .urdf (e.g. mobility.urdf)", path.display())]
    NoUrdfInDirectory {
        /// The directory.
        path: PathBuf,
    },
    /// A directory was given and it holds several `.urdf` files.
    #[error("directory {} holds several .urdf files ({found}); pass the one to load explicitly", path.display())]
    SeveralUrdfsInDirectory {
        /// The directory.
        path: PathBuf,
        /// The `.urdf` file names found, comma separated.
        found: String,
    },
    /// A file is truncated or corrupt, or its parser failed (or panicked).
    #[error("{} is not a valid {format} file: {message}; repair or re-export it", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The format it was read as (`gltf`, `obj`, `mtl`, `png`, ...).
        format: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A file uses a feature this crate does not read.
    #[error("{} uses {what}, which is not supported; convert it to a supported form", path.display())]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The unsupported feature.
        what: String,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} of part {part:?} in {} has a NaN or infinite coordinate; fix the vertex data", path.display())]
    NonFiniteVertex {
        /// The file.
        path: PathBuf,
        /// The part name.
        part: String,
        /// Index of the vertex within the part.
        vertex: usize,
    },
    /// A triangle references a vertex that does not exist.
    #[error(
        "triangle {triangle} of part {part:?} in {} references vertex {vertex}, but the part has {vertex_count} vertices; fix the face indices",
        path.display()
    )]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// The part name.
        part: String,
        /// Index of the triangle within the part.
        triangle: usize,
        /// The out-of-range vertex index.
        vertex: u64,
        /// Number of vertices of the part.
        vertex_count: usize,
    },
    /// Every triangle of a part has zero area.
    #[error("part {part:?} in {} has no triangle with non-zero area; remove the part or fix its geometry", path.display())]
    Degenerate {
        /// The file.
        path: PathBuf,
        /// The part name.
        part: String,
    },
    /// The input holds no triangles at all (points and lines are ignored).
    #[error("{} contains no triangles (points and lines are ignored); export the surfaces as triangles or polygons", path.display())]
    NoGeometry {
        /// The file.
        path: PathBuf,
    },
    /// The input has more triangles than [`crate::IngestOptions::max_triangles`].
    #[error(
        "{} has {count} triangles, more than the limit of {limit}; decimate the mesh or raise IngestOptions::max_triangles",
        path.display()
    )]
    TooManyTriangles {
        /// The file.
        path: PathBuf,
        /// Triangles found or declared (at least this many).
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// The input declares more vertices than 3 x [`crate::IngestOptions::max_triangles`].
    #[error(
        "{} declares {count} vertices, more than the limit of {limit} (3 x max_triangles); decimate the mesh or raise IngestOptions::max_triangles",
        path.display()
    )]
    TooManyVertices {
        /// The file.
        path: PathBuf,
        /// Vertices declared.
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// A file references another file that does not exist.
    #[error(
        "{} references {reference:?}, but {} does not exist; add the missing file or fix the reference",
        path.display(),
        resolved.display()
    )]
    MissingReference {
        /// The referencing file.
        path: PathBuf,
        /// The reference as written in the file.
        reference: String,
        /// Where it was looked for.
        resolved: PathBuf,
    },
    /// A file references a path that is absolute or climbs out of the asset's directory.
    #[error(
        "{} references {reference:?}, which is absolute or leaves the asset's directory; it was not read. Keep referenced files inside the asset's folder and use relative paths",
        path.display()
    )]
    PathTraversal {
        /// The referencing file.
        path: PathBuf,
        /// The reference as written in the file.
        reference: String,
    },
    /// A URDF is well-formed XML but not a usable robot description.
    #[error("{} is not a usable URDF: {message}", path.display())]
    InvalidUrdf {
        /// The URDF file.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A part broke a mesh invariant after ingestion (a bug in this crate rather than the input).
    #[error("part {part:?} from {} is inconsistent: {source}", path.display())]
    Geometry {
        /// The file.
        path: PathBuf,
        /// The part name.
        part: String,
        /// The violated invariant.
        source: GeometryError,
    },
    /// A stored ingested asset ([`crate::IngestedAsset`]) that cannot be read back.
    #[error("the stored ingested asset cannot be read: {message}; run the ingest stage again")]
    Stored {
        /// What is wrong with the bytes.
        message: String,
    },
}

/// Result alias for [`IngestError`].
pub type IngestResult<T> = Result<T, IngestError>;

impl IngestError {
    /// A [`IngestError::Parse`] for `path` read as `format`.
    pub(crate) fn parse(
        path: impl Into<PathBuf>,
        format: &'static str,
        message: impl Into<String>,
    ) -> Self {
        Self::Parse {
            path: path.into(),
            format,
            message: message.into(),
        }
    }

    /// An [`IngestError::InvalidUrdf`] for `path`.
    pub(crate) fn urdf(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::InvalidUrdf {
            path: path.into(),
            message: message.into(),
        }
    }
}
