//! Every entry of an archive read once, in order, under the limits: entry count, unpacked bytes
//! (counted as they are read, never taken from headers), safe paths, no two entries at one path,
//! and only files and folders (links, devices and other special entries are refused).

use std::collections::BTreeSet;
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

use crate::entry_path::safe_components;
use crate::{ArchiveError, ArchiveKind, ArchiveLimits, ArchiveResult};

/// What a walk saw.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct WalkSummary {
    /// Every file's path components, in archive order.
    pub files: Vec<Vec<String>>,
    /// Bytes of all files, as read.
    pub unpacked_bytes: u64,
}

/// Reads every entry of the archive at `path` (of `kind`) in order, and calls `visit` with each
/// entry's path components and, for a file, a reader of its bytes (`None` for a folder). The
/// reader fails once the archive's byte budget is spent ([`ArchiveLimits::byte_budget`]).
///
/// # Errors
/// [`ArchiveError::Unreadable`] for a corrupt or encrypted archive, [`ArchiveError::UnsafeEntry`]
/// and [`ArchiveError::TooLarge`] for what the limits and rules refuse, [`ArchiveError::Io`] for
/// the local disk (opening the archive, or `visit` failing to write).
pub fn walk(
    path: &Path,
    kind: ArchiveKind,
    limits: &ArchiveLimits,
    mut visit: impl FnMut(&[String], Option<&mut dyn Read>) -> std::io::Result<()>,
) -> ArchiveResult<WalkSummary> {
    let file = File::open(path).map_err(ArchiveError::io(format!(
        "opening the archive {}",
        path.display()
    )))?;
    let archive_bytes = file
        .metadata()
        .map_err(ArchiveError::io("reading the archive's size"))?
        .len();
    let mut checks = Checks::new(*limits, archive_bytes);
    match kind {
        ArchiveKind::Zip => walk_zip(BufReader::new(file), &mut checks, &mut visit)?,
        ArchiveKind::Tar => walk_tar(BufReader::new(file), &mut checks, &mut visit)?,
        ArchiveKind::TarGz => walk_tar(
            flate2::read::MultiGzDecoder::new(BufReader::new(file)),
            &mut checks,
            &mut visit,
        )?,
    }
    Ok(WalkSummary {
        files: checks.files_in_order,
        unpacked_bytes: checks.used_bytes,
    })
}

type Visit<'v> = dyn FnMut(&[String], Option<&mut dyn Read>) -> std::io::Result<()> + 'v;

fn walk_zip<R: Read + std::io::Seek>(
    reader: R,
    checks: &mut Checks,
    visit: &mut Visit<'_>,
) -> ArchiveResult<()> {
    let mut zip = zip::ZipArchive::new(reader)
        .map_err(|e| ArchiveError::Unreadable(format!("not a zip file: {e}")))?;
    if zip.len() > checks.limits.max_entries {
        return Err(too_many_entries(checks.limits.max_entries, Some(zip.len())));
    }
    for index in 0..zip.len() {
        let mut entry = zip
            .by_index(index)
            .map_err(|e| ArchiveError::Unreadable(format!("entry {index}: {e}")))?;
        let name = entry
            .name()
            .map_err(|_| ArchiveError::UnsafeEntry {
                entry: format!("#{index}"),
                reason: "its name is not valid UTF-8".into(),
            })?
            .into_owned();
        if entry.is_symlink() {
            return Err(link(&name));
        }
        if entry.is_dir() {
            checks.folder(&name, visit)?;
        } else {
            checks.file(&name, &mut entry, visit)?;
        }
    }
    Ok(())
}

fn walk_tar<R: Read>(reader: R, checks: &mut Checks, visit: &mut Visit<'_>) -> ArchiveResult<()> {
    let mut archive = tar::Archive::new(reader);
    let entries = archive
        .entries()
        .map_err(|e| ArchiveError::Unreadable(format!("not a tar file: {e}")))?;
    for entry in entries {
        let mut entry = entry.map_err(|e| ArchiveError::Unreadable(e.to_string()))?;
        let name = String::from_utf8(entry.path_bytes().into_owned()).map_err(|_| {
            ArchiveError::UnsafeEntry {
                entry: String::from_utf8_lossy(&entry.path_bytes()).into_owned(),
                reason: "its name is not valid UTF-8".into(),
            }
        })?;
        use tar::EntryType as T;
        match entry.header().entry_type() {
            T::Regular | T::Continuous => checks.file(&name, &mut entry, visit)?,
            T::Directory => checks.folder(&name, visit)?,
            // Metadata for the entries after it, not a file.
            T::XGlobalHeader => {}
            T::Symlink | T::Link => return Err(link(&name)),
            other => {
                return Err(ArchiveError::UnsafeEntry {
                    entry: name,
                    reason: format!(
                        "a special entry (tar type {:?}); only files and folders are unpacked",
                        other.as_byte() as char
                    ),
                });
            }
        }
    }
    Ok(())
}

fn link(name: &str) -> ArchiveError {
    ArchiveError::UnsafeEntry {
        entry: name.to_owned(),
        reason: "a link; links are not unpacked (they can point out of the asset's folder): put the file itself in the archive".into(),
    }
}

fn too_many_entries(max: usize, found: Option<usize>) -> ArchiveError {
    ArchiveError::TooLarge(match found {
        Some(n) => format!(
            "the archive holds {n} entries, more than the {max} allowed; submit one asset per archive"
        ),
        None => format!(
            "the archive holds more than the {max} entries allowed; submit one asset per archive"
        ),
    })
}

/// The rules every entry passes, and what was seen so far.
struct Checks {
    limits: ArchiveLimits,
    archive_bytes: u64,
    budget_bytes: u64,
    used_bytes: u64,
    entries: usize,
    files: BTreeSet<Vec<String>>,
    folders: BTreeSet<Vec<String>>,
    files_in_order: Vec<Vec<String>>,
}

impl Checks {
    fn new(limits: ArchiveLimits, archive_bytes: u64) -> Self {
        Self {
            limits,
            archive_bytes,
            budget_bytes: limits.byte_budget(archive_bytes),
            used_bytes: 0,
            entries: 0,
            files: BTreeSet::new(),
            folders: BTreeSet::new(),
            files_in_order: Vec::new(),
        }
    }

    /// Counts an entry and checks its path; returns the components.
    fn path(&mut self, name: &str) -> ArchiveResult<Vec<String>> {
        self.entries += 1;
        if self.entries > self.limits.max_entries {
            return Err(too_many_entries(self.limits.max_entries, None));
        }
        safe_components(name).map_err(|reason| ArchiveError::UnsafeEntry {
            entry: name.to_owned(),
            reason,
        })
    }

    /// Records the folders above `components` (and the folder itself when `itself`), refusing
    /// a folder where a file is.
    fn add_folders(
        &mut self,
        name: &str,
        components: &[String],
        itself: bool,
    ) -> ArchiveResult<()> {
        let upto = components.len() - usize::from(!itself);
        for depth in 1..=upto {
            let folder = &components[..depth];
            if self.files.contains(folder) {
                return Err(clash(name, "a folder where another entry is a file"));
            }
            self.folders.insert(folder.to_vec());
        }
        Ok(())
    }

    fn folder(&mut self, name: &str, visit: &mut Visit<'_>) -> ArchiveResult<()> {
        let components = self.path(name)?;
        self.add_folders(name, &components, true)?;
        visit(&components, None).map_err(ArchiveError::io(format!("creating the folder {name}")))
    }

    fn file(
        &mut self,
        name: &str,
        reader: &mut dyn Read,
        visit: &mut Visit<'_>,
    ) -> ArchiveResult<()> {
        let components = self.path(name)?;
        if self.files.contains(&components) {
            return Err(clash(name, "a second entry with the same path"));
        }
        if self.folders.contains(&components) {
            return Err(clash(name, "a file where another entry is a folder"));
        }
        self.add_folders(name, &components, false)?;
        self.files.insert(components.clone());
        self.files_in_order.push(components.clone());
        let mut counted = Counted {
            inner: reader,
            used: self.used_bytes,
            budget: self.budget_bytes,
            failure: None,
        };
        let visited = visit(&components, Some(&mut counted));
        self.used_bytes = counted.used;
        match (visited, counted.failure) {
            (Ok(()), _) => Ok(()),
            (Err(_), Some(Failure::OverBudget)) => Err(ArchiveError::TooLarge(self.over_budget())),
            (Err(_), Some(Failure::Read(e))) => {
                Err(ArchiveError::Unreadable(format!("entry {name:?}: {e}")))
            }
            (Err(e), None) => Err(ArchiveError::Io {
                context: format!("unpacking {name}"),
                source: e,
            }),
        }
    }

    fn over_budget(&self) -> String {
        let cap = self.limits.max_unpacked_bytes;
        if self.budget_bytes < cap {
            format!(
                "the archive unpacks to more than {} times its size ({} bytes): a decompression bomb, or data that does not belong in an asset",
                self.limits.max_expansion_ratio, self.archive_bytes
            )
        } else {
            format!(
                "the archive unpacks to more than {cap} bytes, the limit; submit a smaller asset"
            )
        }
    }
}

fn clash(name: &str, reason: &str) -> ArchiveError {
    ArchiveError::UnsafeEntry {
        entry: name.to_owned(),
        reason: reason.to_owned(),
    }
}

/// Why a counted read failed.
enum Failure {
    OverBudget,
    Read(String),
}

/// A reader that adds what it reads to the archive's total and fails past the budget; it keeps
/// its own failures so they are told apart from the writer's.
struct Counted<'r> {
    inner: &'r mut dyn Read,
    used: u64,
    budget: u64,
    failure: Option<Failure>,
}

impl Read for Counted<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = match self.inner.read(buf) {
            Ok(n) => n,
            Err(e) => {
                self.failure = Some(Failure::Read(e.to_string()));
                return Err(e);
            }
        };
        self.used += n as u64;
        if self.used > self.budget {
            self.failure = Some(Failure::OverBudget);
            return Err(std::io::Error::other(
                "the archive's unpacked size is over its limit",
            ));
        }
        Ok(n)
    }
}
