//! An archive checked without writing anything ([`inspect`], the API's check of an upload), or
//! unpacked into a folder ([`unpack`], the worker's copy of the asset).

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use crate::walk::walk;
use crate::{ArchiveError, ArchiveKind, ArchiveLimits, ArchiveResult, main_file};

/// What an archive holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Listing {
    /// The asset's main file, `/`-separated, relative to the archive ([`main_file`]).
    pub main_file: String,
    /// Files in the archive.
    pub files: usize,
    /// Bytes of all files once unpacked.
    pub unpacked_bytes: u64,
}

/// Reads the whole archive at `path` (every byte, so a bomb is found as surely as by
/// unpacking) and checks it against `limits` and the entry rules, writing nothing.
///
/// # Errors
/// As [`crate::walk::walk`], and [`ArchiveError::NoAsset`] when no single main file is found.
pub fn inspect(path: &Path, kind: ArchiveKind, limits: &ArchiveLimits) -> ArchiveResult<Listing> {
    let summary = walk(path, kind, limits, |_, reader| {
        if let Some(reader) = reader {
            std::io::copy(reader, &mut std::io::sink())?;
        }
        Ok(())
    })?;
    Ok(Listing {
        main_file: main_file(&summary.files)?,
        files: summary.files.len(),
        unpacked_bytes: summary.unpacked_bytes,
    })
}

/// Unpacks the archive at `path` into `folder` (created if missing; it should be new and
/// empty: files are never overwritten) and returns the main file's path in it with the
/// listing. Nothing is written outside `folder`: paths are checked before use and links are
/// refused. On an error the folder may hold part of the archive; the caller removes it.
///
/// # Errors
/// As [`inspect`], and [`ArchiveError::Io`] when a file cannot be written.
pub fn unpack(
    path: &Path,
    kind: ArchiveKind,
    folder: &Path,
    limits: &ArchiveLimits,
) -> ArchiveResult<(PathBuf, Listing)> {
    std::fs::create_dir_all(folder)
        .map_err(ArchiveError::io(format!("creating {}", folder.display())))?;
    let summary = walk(path, kind, limits, |components, reader| {
        let target = components
            .iter()
            .fold(folder.to_path_buf(), |p, c| p.join(c));
        match reader {
            None => std::fs::create_dir_all(&target),
            Some(reader) => {
                if let Some(parent) = target.parent() {
                    std::fs::create_dir_all(parent)?;
                }
                let mut file: File = OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&target)?;
                std::io::copy(reader, &mut file).map(|_| ())
            }
        }
    })?;
    let main = main_file(&summary.files)?;
    let main_path = main.split('/').fold(folder.to_path_buf(), |p, c| p.join(c));
    Ok((
        main_path,
        Listing {
            main_file: main,
            files: summary.files.len(),
            unpacked_bytes: summary.unpacked_bytes,
        },
    ))
}
