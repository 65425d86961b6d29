//! The set of files one ingestion reads: size-limited reads, the content hash, and the running
//! counters (triangles produced, degenerate triangles dropped) shared by the format readers.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::digest::ContentDigest;
use crate::{IngestError, IngestOptions, IngestResult};

/// State of one call to [`crate::load_asset`].
#[derive(Debug)]
pub(crate) struct Session<'o> {
    /// The caller's options.
    pub(crate) options: &'o IngestOptions,
    /// Canonical directory that every referenced file must stay inside.
    pub(crate) root: PathBuf,
    /// Triangles dropped because they had zero area.
    pub(crate) dropped_degenerate: usize,
    /// What was tolerated (e.g. a missing MTL file), for the report.
    pub(crate) warnings: Vec<String>,
    digest: ContentDigest,
    triangles: usize,
}

impl<'o> Session<'o> {
    /// A session whose references are confined to `root`.
    pub(crate) fn new(options: &'o IngestOptions, root: &Path) -> IngestResult<Self> {
        let root = root.canonicalize().map_err(|source| IngestError::Io {
            path: root.to_path_buf(),
            source,
        })?;
        Ok(Self {
            options,
            root,
            dropped_degenerate: 0,
            warnings: Vec::new(),
            digest: ContentDigest::default(),
            triangles: 0,
        })
    }

    /// Reads a file (the main one or an already resolved reference) within the size limit and
    /// appends its bytes to the content hash.
    pub(crate) fn read(&mut self, path: &Path) -> IngestResult<Vec<u8>> {
        let bytes = read_limited(path, self.options.max_file_bytes)?;
        self.digest.update(&bytes);
        Ok(bytes)
    }

    /// Fails if `count` triangles (declared or produced by one file) exceed the limit.
    pub(crate) fn check_triangles(&self, path: &Path, count: usize) -> IngestResult<()> {
        let limit = self.options.max_triangles;
        if count > limit {
            return Err(IngestError::TooManyTriangles {
                path: path.to_path_buf(),
                count,
                limit,
            });
        }
        Ok(())
    }

    /// Adds triangles produced for the asset so far; fails as soon as the total exceeds the limit
    /// (instancing can multiply a small file's triangles).
    pub(crate) fn add_triangles(&mut self, path: &Path, count: usize) -> IngestResult<()> {
        self.triangles = self.triangles.saturating_add(count);
        self.check_triangles(path, self.triangles)
    }

    /// The content hash of everything read, lowercase hex.
    pub(crate) fn finish_digest(self) -> String {
        self.digest.finish()
    }
}

/// Reads `path` after checking its size against `limit` (from metadata, before reading).
fn read_limited(path: &Path, limit: u64) -> IngestResult<Vec<u8>> {
    let io = |source| IngestError::Io {
        path: path.to_path_buf(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        )));
    }
    let too_large = |size| IngestError::FileTooLarge {
        path: path.to_path_buf(),
        size,
        limit,
    };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    if meta.len() == 0 {
        return Err(IngestError::Empty {
            path: path.to_path_buf(),
        });
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    // The file may grow between the metadata check and the read: never read past the limit.
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    let read = u64::try_from(bytes.len()).unwrap_or(u64::MAX);
    if read > limit {
        return Err(too_large(read));
    }
    if bytes.is_empty() {
        return Err(IngestError::Empty {
            path: path.to_path_buf(),
        });
    }
    Ok(bytes)
}

/// The part name of a single-part file (PLY, STL): its file stem, or `part_0`.
pub(crate) fn part_name_of_file(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "part_0".to_owned(), |s| s.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_over_the_size_limit_is_rejected_from_metadata() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("big.stl");
        std::fs::write(&path, vec![b'x'; 100]).expect("write");
        let err = read_limited(&path, 99).expect_err("too large");
        assert!(
            matches!(
                err,
                IngestError::FileTooLarge {
                    size: 100,
                    limit: 99,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("max_file_bytes"));
        assert_eq!(read_limited(&path, 100).expect("at the limit").len(), 100);
    }

    #[test]
    fn session_counts_triangles_across_files_against_the_limit() {
        let options = IngestOptions {
            max_triangles: 10,
            ..IngestOptions::default()
        };
        let dir = tempfile::tempdir().expect("tempdir");
        let mut s = Session::new(&options, dir.path()).expect("session");
        s.add_triangles(Path::new("a"), 6).expect("below");
        let err = s.add_triangles(Path::new("b"), 6).expect_err("above");
        assert!(matches!(
            err,
            IngestError::TooManyTriangles {
                count: 12,
                limit: 10,
                ..
            }
        ));
    }
}
