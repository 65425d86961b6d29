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

/// Names of the worker's temporary folders start with this, then the worker process's id and
/// a dash.
const SOURCE_DIR_PREFIX: &str = "uniphys-source-";

/// A new temporary folder only its owner can enter (0700), named for the worker process
/// (`uniphys-source-<pid>-…`) so a later start can tell a dead process's leftovers.
fn private_temp_dir() -> std::io::Result<TempDir> {
    let mut builder = tempfile::Builder::new();
    let prefix = format!("{SOURCE_DIR_PREFIX}{}-", std::process::id());
    builder.prefix(&prefix);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o700));
    }
    builder.tempdir()
}

/// Removes the source folders under `temp_dir` left by worker processes that are no longer
/// running (killed before they could clean up; a live process's folders, this one's included,
/// stay). Returns how many were removed. Only where running processes can be listed (`/proc`);
/// elsewhere nothing is removed.
#[must_use]
pub fn sweep_orphaned_sources(temp_dir: &Path) -> usize {
    let proc_root = Path::new("/proc");
    if !proc_root.join("self").exists() {
        return 0;
    }
    let own = std::process::id();
    let Ok(entries) = std::fs::read_dir(temp_dir) else {
        return 0;
    };
    entries
        .flatten()
        .filter(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let Some(pid) = name
                .strip_prefix(SOURCE_DIR_PREFIX)
                .and_then(|rest| rest.split('-').next())
                .and_then(|pid| pid.parse::<u32>().ok())
            else {
                return false;
            };
            pid != own && !proc_root.join(pid.to_string()).exists()
        })
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .filter(|e| std::fs::remove_dir_all(e.path()).is_ok())
        .count()
}

#[cfg(all(test, unix))]
mod tests {
    use std::os::unix::fs::PermissionsExt;

    #[test]
    fn a_dead_workers_folders_are_swept_and_a_live_ones_stay() {
        let temp = tempfile::tempdir().expect("tempdir");
        let make = |name: &str| {
            let dir = temp.path().join(name);
            std::fs::create_dir(&dir).expect("mkdir");
            std::fs::write(dir.join("oven.glb"), b"bytes").expect("write");
            dir
        };
        // Above Linux's largest process id: never a running process.
        let dead = make("uniphys-source-999999999-a1b2");
        let own = make(&format!("uniphys-source-{}-c3d4", std::process::id()));
        let init = make("uniphys-source-1-e5f6");
        let other = make("someone-elses-999999999-x");
        assert_eq!(super::sweep_orphaned_sources(temp.path()), 1);
        assert!(!dead.exists());
        assert!(own.exists() && init.exists() && other.exists());
    }

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
