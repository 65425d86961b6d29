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
        // Private to this user: another local account must not read a tenant's file.
        let dir = private_temp_dir()
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

/// A new temporary folder only its owner can enter (0700), named for the worker.
fn private_temp_dir() -> std::io::Result<TempDir> {
    let mut builder = tempfile::Builder::new();
    builder.prefix("uniphys-source-");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o700));
    }
    builder.tempdir()
}

#[cfg(all(test, unix))]
mod tests {
    use std::os::unix::fs::PermissionsExt;

    #[test]
    fn the_temporary_folder_is_the_owners_only() {
        let dir = super::private_temp_dir().expect("tempdir");
        let mode = std::fs::metadata(dir.path())
            .expect("metadata")
            .permissions()
            .mode();
        assert_eq!(mode & 0o777, 0o700);
    }
}
