//! The submitted file, fetched from the artifact store into a private temporary directory under
//! its original file name (the readers detect the format from the extension).

use std::path::{Path, PathBuf};

use tempfile::TempDir;

use crate::stage::{StageError, StageInput};

/// A local copy of an asset's source; removed on drop.
pub struct SourceFile {
    dir: TempDir,
    path: PathBuf,
}

impl SourceFile {
    /// Fetches `input`'s source.
    pub fn fetch(input: &StageInput) -> Result<Self, StageError> {
        let uri = &input.asset.source_uri;
        let name = uri
            .rsplit('/')
            .next()
            .filter(|n| !n.is_empty() && *n != "." && *n != "..")
            .ok_or_else(|| StageError::Permanent(format!("source key {uri:?} has no file name")))?;
        let dir = tempfile::tempdir()
            .map_err(|e| StageError::Transient(format!("temporary directory: {e}")))?;
        let path = dir.path().join(name);
        // Streamed to disk: sources may be hundreds of megabytes.
        input
            .runtime
            .block_on(input.artifacts.get_to_file(uri, &path))
            .map_err(|e| StageError::Transient(format!("reading {uri}: {e}")))?;
        Ok(Self { dir, path })
    }

    /// A copy already at `dir/name` (tests).
    #[cfg(test)]
    pub(crate) fn in_dir(dir: TempDir, name: &str) -> Self {
        let path = dir.path().join(name);
        Self { dir, path }
    }

    /// Where the copy is.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `message` as the submitter may read it: the worker's temporary folder is never shown (a
    /// file in it is named by its name alone).
    #[must_use]
    pub fn without_local_paths(&self, message: &str) -> String {
        let dir = self.dir.path().display().to_string();
        message
            .replace(&format!("{dir}{}", std::path::MAIN_SEPARATOR), "")
            .replace(&dir, "the asset's folder")
    }

    /// Its file name.
    #[must_use]
    pub fn file_name(&self) -> String {
        self.path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    }
}
