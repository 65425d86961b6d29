/// Errors of the geometry kernel.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GeometryError {
    /// A vertex coordinate was NaN or infinite.
    #[error("vertex {index} has a non-finite coordinate")]
    NonFiniteVertex {
        /// Index of the vertex.
        index: usize,
    },
    /// A triangle referenced a vertex that does not exist.
    #[error(
        "triangle {triangle} references vertex {vertex}, but the mesh has {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The out-of-range vertex index.
        vertex: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A per-vertex or per-face attribute had the wrong length.
    #[error("{attribute} has {got} entries, expected {expected}")]
    AttributeLength {
        /// Attribute name.
        attribute: &'static str,
        /// Entries present.
        got: usize,
        /// Entries expected.
        expected: usize,
    },
    /// The mesh has no triangle with non-zero area.
    #[error("mesh has no triangle with non-zero area")]
    Degenerate,
    /// An operation needed more input than it got (e.g. a plane fit from two points).
    #[error("not enough input: {0}")]
    NotEnoughInput(String),
    /// A parameter was outside its valid range (e.g. a voxel resolution of zero).
    #[error("invalid parameter: {0}")]
    InvalidParameter(String),
    /// The convex hull of a point set could not be computed.
    #[error("convex hull failed: {0}")]
    ConvexHull(String),
}

/// Result alias for [`GeometryError`].
pub type GeometryResult<T> = Result<T, GeometryError>;
