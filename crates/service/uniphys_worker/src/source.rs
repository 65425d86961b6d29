//! The submitted file, fetched from the artifact store into a private temporary directory under
//! its original file name (the readers detect the format from the extension). An archive (a
//! multi-file asset) is unpacked there and its main file stands for the asset.

use std::path::{Path, PathBuf};

use tempfile::TempDir;
use uniphys_archive::{ArchiveKind, ArchiveLimits};

use crate::stage::{StageError, StageInput};

/// A local copy of an asset's source; removed on drop.
pub struct SourceFile {
    dir: TempDir,
    path: PathBuf,
}

impl SourceFile {
    /// Fetches `input`'s source; an archive is unpacked into a folder beside it (under the
    /// default [`ArchiveLimits`], which the API checked it against before storing it) and
    /// [`Self::path`] is its main file (the URDF of a URDF folder). A refused archive fails
    /// the stage for good, naming why.
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
        match ArchiveKind::from_name(name) {
            Some(kind) => Self::unpacked(dir, &path, kind),
            None => Ok(Self { dir, path }),
        }
    }

    /// The archive at `archive` (in `dir`) unpacked into `dir/asset`, then removed.
    fn unpacked(dir: TempDir, archive: &Path, kind: ArchiveKind) -> Result<Self, StageError> {
        let name = archive
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let folder = dir.path().join("asset");
        let (path, _) = uniphys_archive::unpack(archive, kind, &folder, &ArchiveLimits::default())
            .map_err(|e| {
                let message = format!("the archive {name}: {e}");
                if e.is_refusal() {
                    StageError::Permanent(message)
                } else {
                    StageError::Transient(message)
                }
            })?;
        // The unpacked copy is what the stage reads; the archive only takes space.
        let _ = std::fs::remove_file(archive);
        Ok(Self { dir, path })
    }

    /// A copy already at `dir/name` (tests).
    #[cfg(test)]
    pub(crate) fn in_dir(dir: TempDir, name: &str) -> Self {
        let path = dir.path().join(name);
        Self { dir, path }
    }

    /// An archive already at `dir/name`, unpacked as [`Self::fetch`] does (tests).
    #[cfg(test)]
    pub(crate) fn unpacked_in_dir(dir: TempDir, name: &str) -> Result<Self, StageError> {
        let path = dir.path().join(name);
        let kind = ArchiveKind::from_name(name).expect("an archive name");
        Self::unpacked(dir, &path, kind)
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

    /// `bytes` of an output file as the submitter may read it: a JSON or text file (a report
    /// whose warnings name an input file by its path) with the worker's temporary folder taken
    /// out, as [`Self::without_local_paths`]; other files as they are. The output then does not
    /// depend on where this attempt ran, so a retried stage writes the same bytes.
    #[must_use]
    pub fn without_local_paths_in(&self, name: &str, bytes: Vec<u8>) -> Vec<u8> {
        let text_file = [".json", ".txt", ".log"]
            .iter()
            .any(|ending| name.to_ascii_lowercase().ends_with(ending));
        match String::from_utf8(bytes) {
            Ok(text) if text_file => self.without_local_paths(&text).into_bytes(),
            Ok(text) => text.into_bytes(),
            Err(e) => e.into_bytes(),
        }
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
    fn an_archive_is_unpacked_and_its_main_file_stands_for_the_asset() {
        let dir = super::private_temp_dir().expect("tempdir");
        let folder = tempfile::tempdir().expect("tempdir");
        std::fs::create_dir_all(folder.path().join("meshes")).expect("mkdir");
        std::fs::write(folder.path().join("robot.urdf"), b"<robot name=\"r\"/>").expect("urdf");
        std::fs::write(folder.path().join("meshes/a.obj"), b"v 0 0 0\n").expect("obj");
        uniphys_archive::pack_folder(folder.path(), &dir.path().join("robot.tar.gz"))
            .expect("pack");
        let source = super::SourceFile::unpacked_in_dir(dir, "robot.tar.gz").expect("unpacked");
        assert_eq!(source.file_name(), "robot.urdf");
        let asset = source.path().parent().expect("the asset's folder");
        assert!(asset.join("meshes/a.obj").is_file());
        assert!(!asset.parent().expect("dir").join("robot.tar.gz").exists());
        assert_eq!(
            source.without_local_paths(&format!(
                "cannot read {}",
                asset.join("meshes/a.obj").display()
            )),
            "cannot read asset/meshes/a.obj"
        );
    }

    #[test]
    fn reports_leave_the_temporary_folder_out_and_meshes_are_untouched() {
        let dir = super::private_temp_dir().expect("tempdir");
        let shown = dir.path().display().to_string();
        let source = super::SourceFile::in_dir(dir, "chair.obj");
        let report =
            format!("{{\"message\": \"{shown}/textures/wood.mtl names a missing image\"}}");
        let cleaned = source.without_local_paths_in("report.json", report.into_bytes());
        assert_eq!(
            String::from_utf8(cleaned).expect("text"),
            "{\"message\": \"textures/wood.mtl names a missing image\"}"
        );
        let mesh = format!("# {shown}\nv 0 0 0\n").into_bytes();
        assert_eq!(
            source.without_local_paths_in("part.obj", mesh.clone()),
            mesh
        );
    }

    #[test]
    fn a_refused_archive_fails_the_stage_for_good() {
        let dir = super::private_temp_dir().expect("tempdir");
        std::fs::write(dir.path().join("x.zip"), b"not a zip").expect("write");
        let error = super::SourceFile::unpacked_in_dir(dir, "x.zip")
            .err()
            .expect("refused");
        assert!(
            matches!(&error, crate::stage::StageError::Permanent(m) if m.contains("x.zip") && m.contains("cannot be read")),
            "{error:?}"
        );
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
