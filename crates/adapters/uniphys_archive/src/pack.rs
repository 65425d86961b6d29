//! A folder packed into a tar.gz with the same bytes every time: entries in path order, times,
//! owners and modes fixed, no name or time in the gzip header. The same folder submitted twice
//! is then the same content, and so the same asset.

use std::fs::File;
use std::io::{BufWriter, Read, Write};
use std::path::Path;

use crate::{ArchiveError, ArchiveResult, main_file};

/// What [`pack_folder`] packed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PackSummary {
    /// Files packed.
    pub files: usize,
    /// Their bytes.
    pub bytes: u64,
    /// The asset's main file, relative to the folder ([`main_file`]).
    pub main_file: String,
}

/// Packs the files under `folder` (hidden files and folders, whose names start with a dot,
/// left out) into a new gzip-compressed tar at `out`, paths relative to `folder`.
///
/// # Errors
/// [`ArchiveError::UnsafeEntry`] for a link or special file in the folder (the service refuses
/// links; copy the file in), [`ArchiveError::NoAsset`] when the folder holds no single main
/// file, [`ArchiveError::Io`] for the disk.
pub fn pack_folder(folder: &Path, out: &Path) -> ArchiveResult<PackSummary> {
    let mut files = Vec::new();
    collect(folder, &mut Vec::new(), &mut files)?;
    let main = main_file(&files)?;
    let writer =
        File::create(out).map_err(ArchiveError::io(format!("creating {}", out.display())))?;
    let gz = flate2::write::GzEncoder::new(BufWriter::new(writer), flate2::Compression::new(6));
    let mut tar = DeterministicTar::new(gz);
    let mut bytes = 0u64;
    for components in &files {
        let source = components
            .iter()
            .fold(folder.to_path_buf(), |p, c| p.join(c));
        let context = format!("packing {}", source.display());
        let file = File::open(&source).map_err(ArchiveError::io(&context))?;
        let size = file.metadata().map_err(ArchiveError::io(&context))?.len();
        tar.append(&components.join("/"), size, file)
            .map_err(ArchiveError::io(&context))?;
        bytes += size;
    }
    tar.finish()
        .and_then(|gz| gz.finish())
        .and_then(|mut w| w.flush())
        .map_err(ArchiveError::io(format!("writing {}", out.display())))?;
    Ok(PackSummary {
        files: files.len(),
        bytes,
        main_file: main,
    })
}

/// A tar written with fixed times, owners and modes, so the same files in the same order give
/// the same bytes (long paths as GNU long names).
pub struct DeterministicTar<W: Write> {
    builder: tar::Builder<W>,
}

impl<W: Write> DeterministicTar<W> {
    /// A tar written to `writer`.
    pub fn new(writer: W) -> Self {
        Self {
            builder: tar::Builder::new(writer),
        }
    }

    /// Appends a file of `size` bytes at `path` (`/`-separated, relative) read from `data`.
    ///
    /// # Errors
    /// The writer's, or a path the tar format refuses.
    pub fn append(&mut self, path: &str, size: u64, data: impl Read) -> std::io::Result<()> {
        let mut header = tar::Header::new_gnu();
        header.set_entry_type(tar::EntryType::Regular);
        header.set_size(size);
        header.set_mode(0o644);
        header.set_mtime(0);
        header.set_uid(0);
        header.set_gid(0);
        self.builder.append_data(&mut header, path, data)
    }

    /// Ends the tar and returns the writer.
    ///
    /// # Errors
    /// The writer's.
    pub fn finish(self) -> std::io::Result<W> {
        self.builder.into_inner()
    }
}

/// The files under `folder/prefix`, sorted by name at every level, as path components.
fn collect(
    folder: &Path,
    prefix: &mut Vec<String>,
    out: &mut Vec<Vec<String>>,
) -> ArchiveResult<()> {
    let here = prefix.iter().fold(folder.to_path_buf(), |p, c| p.join(c));
    let mut entries: Vec<(String, std::fs::FileType)> = std::fs::read_dir(&here)
        .map_err(ArchiveError::io(format!(
            "reading the folder {}",
            here.display()
        )))?
        .map(|e| {
            let e = e?;
            Ok((e.file_name().to_string_lossy().into_owned(), e.file_type()?))
        })
        .collect::<std::io::Result<_>>()
        .map_err(ArchiveError::io(format!(
            "reading the folder {}",
            here.display()
        )))?;
    entries.sort_by(|a, b| a.0.cmp(&b.0));
    for (name, kind) in entries {
        if name.starts_with('.') {
            continue;
        }
        prefix.push(name);
        if kind.is_dir() {
            collect(folder, prefix, out)?;
        } else if kind.is_file() {
            out.push(prefix.clone());
        } else {
            return Err(ArchiveError::UnsafeEntry {
                entry: prefix.join("/"),
                reason: "a link or special file; the service unpacks only files and folders: copy the file itself into the folder".into(),
            });
        }
        prefix.pop();
    }
    Ok(())
}
